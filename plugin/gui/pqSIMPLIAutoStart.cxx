// Showing MLIs as captured in the GUI without settings (see pqSIMPLIAutoStart.h).
#include "pqSIMPLIAutoStart.h"

#include <QFile>
#include <QMainWindow>
#include <QMenu>
#include <QMenuBar>
#include <QStringList>
#include <QTimer>

#include <pqApplicationCore.h>
#include <pqCoreUtilities.h>
#include <pqDataRepresentation.h>
#include <pqOutputPort.h>
#include <pqRenderView.h>
#include <pqServerManagerModel.h>
#include <vtkCommand.h>
#include <vtkPVDataInformation.h>

#include "pqSIMPLIMLIDisplay.h"

pqSIMPLIAutoStart::pqSIMPLIAutoStart(QObject* parent) : QObject(parent) {}

void pqSIMPLIAutoStart::startup() {
  pqServerManagerModel* model = pqApplicationCore::instance()->getServerManagerModel();
  connect(model, &pqServerManagerModel::proxyAdded, this, &pqSIMPLIAutoStart::onProxyAdded);
  connect(model, &pqServerManagerModel::viewAdded, this, &pqSIMPLIAutoStart::onViewAdded);
  for (pqView* view : model->findItems<pqView*>())
    onViewAdded(view);
}

namespace {

// Appends "Menu/Submenu/Action" for every action under `menu` whose path mentions SIMPLI.
void listSimpliActions(QMenu* menu, const QString& path, QStringList& out) {
  for (QAction* action : menu->actions()) {
    const QString item = path + "/" + action->text().remove('&');
    if (action->menu())
      listSimpliActions(action->menu(), item, out);
    else if (item.contains("SIMPLI"))
      out << item;
  }
}

// For the GUI test (tests/vtk/gui_mli.sh): the menu entries of the plugin as the user sees
// them, written to $SIMPLI_GUI_MENU_DUMP when that is set. Nothing happens otherwise.
void dumpMenus() {
  const QByteArray file = qgetenv("SIMPLI_GUI_MENU_DUMP");
  auto* window = qobject_cast<QMainWindow*>(pqCoreUtilities::mainWidget());
  if (file.isEmpty() || !window)
    return;
  QStringList entries;
  for (QAction* action : window->menuBar()->actions())
    if (action->menu())
      listSimpliActions(action->menu(), action->text().remove('&'), entries);
  QFile out(QString::fromLocal8Bit(file));
  if (out.open(QIODevice::WriteOnly | QIODevice::Truncate | QIODevice::Text))
    out.write(entries.join('\n').toUtf8() + "\n");
}

} // namespace

void pqSIMPLIAutoStart::shutdown() {
  Seen.clear();
}

void pqSIMPLIAutoStart::onViewAdded(pqView* view) {
  if (auto* renderView = qobject_cast<pqRenderView*>(view))
    pqCoreUtilities::connect(renderView->getProxy(), vtkCommand::ResetCameraEvent, this,
                             SLOT(setUpNewRepresentations()));
}

void pqSIMPLIAutoStart::onProxyAdded(pqProxy* proxy) {
  if (qobject_cast<pqDataRepresentation*>(proxy))
    QTimer::singleShot(0, this, &pqSIMPLIAutoStart::setUpNewRepresentations);
}

// Sets up every representation not seen before whose data is an MLI by now; one whose data
// is computed and not an MLI is not looked at again, one not computed yet is.
void pqSIMPLIAutoStart::setUpNewRepresentations() {
  dumpMenus();
  Seen.removeAll(nullptr);
  pqServerManagerModel* model = pqApplicationCore::instance()->getServerManagerModel();
  for (pqRenderView* view : model->findItems<pqRenderView*>()) {
    for (pqRepresentation* item : view->getRepresentations()) {
      auto* representation = qobject_cast<pqDataRepresentation*>(item);
      pqOutputPort* port = representation ? representation->getOutputPortFromInput() : nullptr;
      if (!port || Seen.contains(representation))
        continue;
      if (simpli::pv::showAsCaptured(representation)) {
        simpli::pv::applyReferenceCamera(view, port);
        Seen.append(representation);
      } else if (port->getDataInformation()->GetDataSetType() != -1) {
        Seen.append(representation); // computed, not an MLI
      }
    }
  }
}
