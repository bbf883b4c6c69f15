// The SIMPLI menu (see pqSIMPLIActions.h).
#include "pqSIMPLIActions.h"

#include <QAction>
#include <QMessageBox>

#include <pqActiveObjects.h>
#include <pqCoreUtilities.h>
#include <pqDataRepresentation.h>
#include <pqOutputPort.h>
#include <pqPipelineSource.h>
#include <pqRenderView.h>

#include "pqSIMPLIMLIDisplay.h"

pqSIMPLIActions::pqSIMPLIActions(QObject* parent) : QActionGroup(parent) {
  setExclusive(false);
  QAction* apply = new QAction(tr("Apply MLI Reference Camera"), this);
  apply->setObjectName("actionSIMPLIApplyReferenceCamera");
  apply->setToolTip(tr("Look through the active MLI's reference camera, showing its layers "
                       "as captured (colours unmapped, back-to-front blending)"));
  addAction(apply);
  connect(apply, &QAction::triggered, this, &pqSIMPLIActions::applyReferenceCamera);
  pqActiveObjects& active = pqActiveObjects::instance();
  connect(&active, &pqActiveObjects::portChanged, this, &pqSIMPLIActions::updateEnableState);
  connect(&active, &pqActiveObjects::viewChanged, this, &pqSIMPLIActions::updateEnableState);
  connect(&active, &pqActiveObjects::dataUpdated, this, &pqSIMPLIActions::updateEnableState);
  updateEnableState();
}

void pqSIMPLIActions::updateEnableState() {
  pqActiveObjects& active = pqActiveObjects::instance();
  const bool enabled = qobject_cast<pqRenderView*>(active.activeView()) &&
                       simpli::pv::mliLayerCount(active.activePort()) > 0;
  for (QAction* action : actions())
    action->setEnabled(enabled);
}

void pqSIMPLIActions::applyReferenceCamera() {
  pqActiveObjects& active = pqActiveObjects::instance();
  auto* view = qobject_cast<pqRenderView*>(active.activeView());
  pqOutputPort* port = active.activePort();
  if (view && port)
    if (auto* representation = port->getRepresentation(view))
      simpli::pv::showAsCaptured(representation);
  QString why;
  if (!simpli::pv::applyReferenceCamera(view, port, &why))
    QMessageBox::warning(pqCoreUtilities::mainWidget(), tr("Apply MLI Reference Camera"), why);
}
