// The SIMPLI plugin's GUI behaviour (issue 11 item 5): an MLI shown in a render view is shown
// as captured, through its reference camera, with nothing for the user to set
// (pqSIMPLIMLIDisplay.h). Started by ParaView when the plugin loads in the GUI.
//
// When: ParaView sets a new representation's colouring and resets the camera after the
// representation exists (pqApplyBehavior in the GUI; paraview.simple's first Render), so the
// views are scanned at every camera reset (the view proxy's ResetCameraEvent, which comes after
// the reset) and once the event that added a representation has been handled. Each
// representation is set up once: what the user changes afterwards stays.
#pragma once

#include <QList>
#include <QObject>
#include <QPointer>

class pqDataRepresentation;
class pqProxy;
class pqView;

class pqSIMPLIAutoStart : public QObject {
  Q_OBJECT

public:
  explicit pqSIMPLIAutoStart(QObject* parent = nullptr);
  void startup();
  void shutdown();

private Q_SLOTS:
  void onProxyAdded(pqProxy* proxy);
  void onViewAdded(pqView* view);
  void setUpNewRepresentations();

private:
  /// Representations already looked at: set up as MLIs, or computed and not MLIs.
  QList<QPointer<pqDataRepresentation>> Seen;
};
