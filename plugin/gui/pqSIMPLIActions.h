// The SIMPLI menu of the GUI: "Apply MLI Reference Camera" puts the active render view back at
// the active source's MLI camera and shows it as captured (pqSIMPLIMLIDisplay.h), for when the
// user has moved away or added the MLI to a view that already held data.
#pragma once

#include <QActionGroup>

class pqSIMPLIActions : public QActionGroup {
  Q_OBJECT

public:
  explicit pqSIMPLIActions(QObject* parent);

private Q_SLOTS:
  void applyReferenceCamera();
  void updateEnableState();
};
