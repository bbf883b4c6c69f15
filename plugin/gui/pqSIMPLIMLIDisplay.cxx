// Showing an MLI in a ParaView render view (see pqSIMPLIMLIDisplay.h).
#include "pqSIMPLIMLIDisplay.h"

#include <algorithm>
#include <exception>

#include <pqDataRepresentation.h>
#include <pqOutputPort.h>
#include <pqPipelineSource.h>
#include <pqRenderView.h>
#include <vtkAlgorithm.h>
#include <vtkCamera.h>
#include <vtkDataObject.h>
#include <vtkFieldData.h>
#include <vtkNew.h>
#include <vtkPartitionedDataSetCollection.h>
#include <vtkSMPVRepresentationProxy.h>
#include <vtkSMPropertyHelper.h>
#include <vtkSMRenderViewProxy.h>
#include <vtkSMSourceProxy.h>

#include "SIMPLILayerActors.h"
#include "SIMPLIMLIToVTK.h"

namespace simpli::pv {
namespace {

/// The collection at `port` when it is computed in this process (builtin session), else null.
vtkPartitionedDataSetCollection* localCollection(pqOutputPort* port) {
  if (!port || !port->getSource())
    return nullptr;
  auto* source = vtkSMSourceProxy::SafeDownCast(port->getSource()->getProxy());
  auto* algorithm = source ? vtkAlgorithm::SafeDownCast(source->GetClientSideObject()) : nullptr;
  if (!algorithm || port->getPortNumber() >= algorithm->GetNumberOfOutputPorts())
    return nullptr;
  return vtkPartitionedDataSetCollection::SafeDownCast(
      algorithm->GetOutputDataObject(port->getPortNumber()));
}

bool hasCamera(vtkPartitionedDataSetCollection* collection) {
  vtkFieldData* fd = collection ? collection->GetFieldData() : nullptr;
  return fd && fd->GetAbstractArray(vtkmli::kIntrinsicsArray) &&
         fd->GetAbstractArray(vtkmli::kExtrinsicsArray) &&
         fd->GetAbstractArray(vtkmli::kImageSizeArray);
}

} // namespace

int mliLayerCount(pqOutputPort* port) {
  vtkPartitionedDataSetCollection* collection = localCollection(port);
  return hasCamera(collection) ? static_cast<int>(collection->GetNumberOfPartitionedDataSets()) : 0;
}

bool showAsCaptured(pqDataRepresentation* representation) {
  if (!representation)
    return false;
  const int layers = mliLayerCount(representation->getOutputPortFromInput());
  vtkSMProxy* proxy = representation->getProxy();
  if (layers == 0 || !proxy->GetProperty("MapScalars"))
    return false;
  vtkSMPropertyHelper(proxy, "Representation").Set("Surface");
  if (auto* pvProxy = vtkSMPVRepresentationProxy::SafeDownCast(proxy))
    pvProxy->SetScalarColoring("RGBA", vtkDataObject::POINT);
  vtkSMPropertyHelper(proxy, "MapScalars").Set(0);
  vtkSMPropertyHelper(proxy, "Ambient").Set(1.0);
  vtkSMPropertyHelper(proxy, "Diffuse").Set(0.0);
  vtkSMPropertyHelper(proxy, "Specular").Set(0.0);
  proxy->UpdateVTKObjects();
  if (auto* view = qobject_cast<pqRenderView*>(representation->getView())) {
    vtkSMProxy* viewProxy = view->getProxy();
    vtkSMPropertyHelper(viewProxy, "DepthPeeling").Set(1);
    vtkSMPropertyHelper peels(viewProxy, "MaximumNumberOfPeels");
    peels.Set(std::max(peels.GetAsInt(), layers + 1));
    viewProxy->UpdateVTKObjects();
  }
  return true;
}

bool applyReferenceCamera(pqRenderView* view, pqOutputPort* port, QString* why) {
  auto say = [why](const QString& text) {
    if (why)
      *why = text;
    return false;
  };
  if (!view)
    return say("no render view is active");
  vtkPartitionedDataSetCollection* collection = localCollection(port);
  if (!hasCamera(collection))
    return say("the active source is not an MLI computed in this process (its output has no "
               "CameraIntrinsics/CameraExtrinsics/CameraImageSize field data)");
  try {
    const scene::Camera camera =
        vtkmli::cameraFromFieldData(collection->GetFieldData(), "MLI camera");
    vtkNew<vtkCamera> reference;
    vtkrender::setCamera(reference, camera, 1e-3, 1e6);
    vtkSMRenderViewProxy* viewProxy = view->getRenderViewProxy();
    vtkCamera* active = viewProxy->GetActiveCamera();
    active->SetPosition(reference->GetPosition());
    active->SetFocalPoint(reference->GetFocalPoint());
    active->SetViewUp(reference->GetViewUp());
    active->SetViewAngle(reference->GetViewAngle());
    active->SetWindowCenter(reference->GetWindowCenter()[0], reference->GetWindowCenter()[1]);
    active->SetParallelProjection(0);
    viewProxy->SynchronizeCameraProperties();
    vtkSMPropertyHelper(viewProxy, "CenterOfRotation").Set(reference->GetFocalPoint(), 3);
    viewProxy->UpdateVTKObjects();
    view->render();
  } catch (const std::exception& e) {
    return say(QString::fromStdString(e.what()));
  }
  return true;
}

} // namespace simpli::pv
