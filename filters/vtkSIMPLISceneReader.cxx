#include "vtkSIMPLISceneReader.h"

#include "SIMPLIFilter.h"
#include "SIMPLIMLIToVTK.h"
#include "SIMPLISceneToVTK.h"

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkCompositeDataSet.h>
#include <vtkDataAssembly.h>
#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkImageData.h>
#include <vtkInformation.h>
#include <vtkInformationVector.h>
#include <vtkIntArray.h>
#include <vtkObjectFactory.h>
#include <vtkPartitionedDataSetCollection.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>
#include <vtkStringArray.h>

#include "simpli/error.h"
#include "simpli/model/scene/scene.h"

#include <exception>

vtkStandardNewMacro(vtkSIMPLISceneReader);

namespace {

vtkSmartPointer<vtkIntArray> intValue(const char* name, int value) {
  auto a = vtkSmartPointer<vtkIntArray>::New();
  a->SetName(name);
  a->InsertNextValue(value);
  return a;
}

vtkSmartPointer<vtkStringArray> stringValue(const char* name, const std::string& value) {
  auto a = vtkSmartPointer<vtkStringArray>::New();
  a->SetName(name);
  a->InsertNextValue(value);
  return a;
}

// One polyline per camera: the base rectangle (image corners at depth `scale`) and the four
// edges to the centre, drawn as c0 c1 c2 c3 c0 C c1 c2 C c3 (c1-c2 twice: one polyline cannot
// trace the 8 edges without repeating one).
void buildFrustums(const std::vector<simpli::scene::Camera>& cameras, double scale,
                   vtkPolyData* out) {
  auto points = vtkSmartPointer<vtkPoints>::New();
  points->SetDataTypeToDouble();
  auto lines = vtkSmartPointer<vtkCellArray>::New();
  auto viewIndex = vtkSmartPointer<vtkIntArray>::New();
  viewIndex->SetName(simpli::vtkscene::kViewIndexArray);
  const double corners[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  for (std::size_t v = 0; v < cameras.size(); ++v) {
    const simpli::scene::Camera& cam = cameras[v];
    const vtkIdType base = points->GetNumberOfPoints();
    const Eigen::Vector3d C = cam.centre();
    points->InsertNextPoint(C.x(), C.y(), C.z());
    for (const auto& uv : corners) {
      const Eigen::Vector3d X = cam.backproject({uv[0], uv[1]}, scale);
      points->InsertNextPoint(X.x(), X.y(), X.z());
    }
    const int order[10] = {1, 2, 3, 4, 1, 0, 2, 3, 0, 4};
    lines->InsertNextCell(10);
    for (int o : order)
      lines->InsertCellPoint(base + o);
    viewIndex->InsertNextValue(static_cast<int>(v));
  }
  out->SetPoints(points);
  out->SetLines(lines);
  out->GetCellData()->AddArray(viewIndex);
}

} // namespace

vtkSIMPLISceneReader::vtkSIMPLISceneReader() {
  this->SetNumberOfInputPorts(0);
  this->SetNumberOfOutputPorts(2);
}

vtkSIMPLISceneReader::~vtkSIMPLISceneReader() {
  this->SetFileName(nullptr);
  this->SetImagesDirectory(nullptr);
}

int vtkSIMPLISceneReader::FillOutputPortInformation(int port, vtkInformation* info) {
  if (port == 1) {
    info->Set(vtkDataObject::DATA_TYPE_NAME(), "vtkPolyData");
    return 1;
  }
  return this->Superclass::FillOutputPortInformation(port, info);
}

int vtkSIMPLISceneReader::CanReadFile(const char* name) {
  if (!name || !*name)
    return 0;
  try {
    simpli::scene::detectSceneFormat(name);
    return 1;
  } catch (const std::exception&) {
    return 0;
  }
}

namespace {

// The scene's views as images with their cameras (one partition each, assembly
// /Scene/Views/ViewNN) and the scene's bounds, normalisation, format and view count as field
// data. False when aborted.
bool viewsToVTK(const simpli::scene::Scene& scene, vtkPartitionedDataSetCollection* views,
                const simpli::vtkfilter::Progress& progress) {
  auto assembly = vtkSmartPointer<vtkDataAssembly>::New();
  assembly->SetRootNodeName("Scene");
  const int viewsNode = assembly->AddNode("Views");
  for (std::size_t v = 0; v < scene.views.size(); ++v) {
    if (!progress(static_cast<double>(v) / scene.views.size()))
      return false;
    const simpli::scene::SceneView& view = scene.views[v];
    auto image = vtkSmartPointer<vtkImageData>::New();
    simpli::vtkscene::imageToVTK(view.image, image);
    vtkFieldData* fd = image->GetFieldData();
    simpli::vtkmli::addCameraFieldData(fd, view.camera);
    fd->AddArray(intValue(simpli::vtkscene::kViewIndexArray, static_cast<int>(v)));
    fd->AddArray(stringValue(simpli::vtkscene::kViewNameArray, view.name));
    fd->AddArray(stringValue(simpli::vtkscene::kImagePathArray, view.imagePath));
    const unsigned int index = static_cast<unsigned int>(v);
    const std::string name = simpli::vtkscene::viewName(static_cast<int>(v));
    views->SetPartition(index, 0, image);
    views->GetMetaData(index)->Set(vtkCompositeDataSet::NAME(), name.c_str());
    assembly->AddDataSetIndex(assembly->AddNode(name.c_str(), viewsNode), index);
  }
  views->SetDataAssembly(assembly);
  vtkFieldData* fd = views->GetFieldData();
  simpli::vtkscene::addNearFar(fd, scene.near, scene.far);
  auto scale = vtkSmartPointer<vtkDoubleArray>::New();
  scale->SetName(simpli::vtkscene::kNormalisationScaleArray);
  scale->InsertNextValue(scene.normalisation.scale);
  fd->AddArray(scale);
  fd->AddArray(
      stringValue(simpli::vtkscene::kSceneFormatArray, simpli::scene::toString(scene.format)));
  fd->AddArray(intValue(simpli::vtkscene::kNumberOfViewsArray, static_cast<int>(scene.size())));
  return true;
}

} // namespace

int vtkSIMPLISceneReader::RequestData(vtkInformation* vtkNotUsed(request),
                                      vtkInformationVector** vtkNotUsed(inputVector),
                                      vtkInformationVector* outputVector) {
  vtkPartitionedDataSetCollection* views =
      vtkPartitionedDataSetCollection::GetData(outputVector, 0);
  vtkPolyData* frustums = vtkPolyData::GetData(outputVector, 1);
  if (!views || !frustums) {
    vtkErrorMacro(<< "Missing outputs (a vtkPartitionedDataSetCollection and a vtkPolyData)");
    return 0;
  }
  views->Initialize();
  frustums->Initialize();
  if (!this->FileName || !*this->FileName) {
    vtkErrorMacro(
        << "FileName is not set (expected a scene folder: LLFF, COLMAP or RealEstate10K)");
    return 0;
  }

  const std::string what = std::string("Cannot read scene '") + this->FileName + "'";
  return simpli::vtkfilter::runRequest(
      this, what,
      [&](const simpli::vtkfilter::Progress& progress) {
        simpli::scene::SceneReadOptions options;
        options.sizeMultiple = this->SizeMultiple;
        if (this->ImagesDirectory)
          options.imagesDir = this->ImagesDirectory;
        if (!this->Normalise)
          options.normalisation.mode = simpli::scene::NormalisationMode::None;
        progress(0.0);
        const simpli::scene::Scene scene = simpli::scene::readScene(this->FileName, options);
        // Reading and decoding the images is nearly all of the work.
        if (!progress(0.8))
          return; // aborted: empty outputs, no error
        if (!viewsToVTK(scene, views, progress.range(0.8, 1.0))) {
          views->Initialize();
          return;
        }
        buildFrustums(scene.cameras(), this->FrustumScale, frustums);
        simpli::vtkscene::addNearFar(frustums->GetFieldData(), scene.near, scene.far);
        progress(1.0);
      },
      [views, frustums] {
        views->Initialize();
        frustums->Initialize();
      });
}

void vtkSIMPLISceneReader::PrintSelf(ostream& os, vtkIndent indent) {
  this->Superclass::PrintSelf(os, indent);
  os << indent << "FileName: " << (this->FileName ? this->FileName : "(none)") << "\n";
  os << indent << "FrustumScale: " << this->FrustumScale << "\n";
  os << indent << "Normalise: " << this->Normalise << "\n";
  os << indent << "SizeMultiple: " << this->SizeMultiple << "\n";
  os << indent
     << "ImagesDirectory: " << (this->ImagesDirectory ? this->ImagesDirectory : "(images)") << "\n";
}
