/**
 * @class   vtkSIMPLIRenderView
 * @brief   renders a SIMPLI multi-layer image (MLI) into a camera with the OpenCL rasterizer
 *
 * Input port 0: the MLI as layer meshes (vtkPartitionedDataSetCollection as vtkMLIReader
 * produces: Color, Alpha and Depth point arrays per layer, the reference camera in the field
 * data). Input port 1 (optional): a scene, as vtkSIMPLISceneReader's port 0 produces (views
 * with their cameras, NearFar bounds).
 *
 * The camera (CameraMode):
 *   - CAMERA_REFERENCE: the MLI's own reference camera;
 *   - CAMERA_SCENE_VIEW: the camera of view ViewIndex of the scene (port 1 required);
 *   - CAMERA_EXPLICIT: Intrinsics (fx, fy, cx, cy relative to the image size), Extrinsics
 *     (world->camera [R | t], 3 x 4 row-major) and ImageSize (0 = the MLI's size);
 *   - CAMERA_TRAJECTORY: frame FrameIndex of NumberOfFrames of a spiral or orbit path around
 *     the MLI's reference camera (simpli/model/trajectory.h); TrajectoryRadii (0, 0, 0 = from
 *     the scene cameras' spread, or 5 % of the focus depth without a scene) and FocusDepth
 *     (0 = from the scene's NearFar, or the MLI's depth range). In this mode the output
 *     publishes TIME_STEPS 0 .. NumberOfFrames-1, so ParaView's animation plays the path; a
 *     requested time t selects frame round(t) (FrameIndex applies when no time is requested).
 *
 * Rendering (simpli/model/rasterizer.h): depth-sorted fragments of all layers (MaxFragments
 * per pixel), the farthest fragment opaque, front-to-back composite over black; Interpolation
 * SCREEN_LINEAR (the reference implementation's) or PERSPECTIVE_CORRECT (what OpenGL renders).
 * Width / Height: output size; 0 = the camera's own size (one of them 0: keeps the aspect
 * ratio). Relative intrinsics do not change with the size. The output's WHOLE_EXTENT is
 * published in RequestInformation (image pipelines and ParaView's slice view need it); when
 * Width and Height do not fix it, the inputs are updated there to read their cameras.
 *
 * Output: vtkImageData (W x H x 1, VTK row order: row 0 = bottom image row) with point data
 * "RGB" (uchar x 3, round(255 c), the active scalars), "Depth" (float: composited target-camera
 * z, 0 where nothing is hit) and "Opacity" (float); field data: the camera used
 * (CameraIntrinsics, CameraExtrinsics, CameraImageSize) and "FrameIndex" (int, -1 outside the
 * trajectory mode).
 *
 * Errors (no MLI, invalid camera arrays, view index out of range, missing scene, bad
 * trajectory parameters, OpenCL failures) are reported with vtkErrorMacro naming the property
 * or array and the value; the request fails with an empty image.
 */

#ifndef vtkSIMPLIRenderView_h
#define vtkSIMPLIRenderView_h

#include "vtkSimpliFiltersModule.h" // for export macro
#include <vtkImageAlgorithm.h>

class VTKSIMPLIFILTERS_EXPORT vtkSIMPLIRenderView : public vtkImageAlgorithm {
public:
  static vtkSIMPLIRenderView* New();
  vtkTypeMacro(vtkSIMPLIRenderView, vtkImageAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /**
   * Convenience for port 1 (the scene); port 0 is SetInputConnection(0, ...).
   */
  void SetSceneConnection(vtkAlgorithmOutput* output) { this->SetInputConnection(1, output); }

  enum CameraModes {
    CAMERA_REFERENCE = 0,
    CAMERA_SCENE_VIEW = 1,
    CAMERA_EXPLICIT = 2,
    CAMERA_TRAJECTORY = 3
  };
  enum TrajectoryTypes { TRAJECTORY_SPIRAL = 0, TRAJECTORY_ORBIT = 1 };
  enum Interpolations { SCREEN_LINEAR = 0, PERSPECTIVE_CORRECT = 1 };

  ///@{
  /**
   * Where the camera comes from (see the class description). Default CAMERA_REFERENCE.
   */
  vtkSetClampMacro(CameraMode, int, CAMERA_REFERENCE, CAMERA_TRAJECTORY);
  vtkGetMacro(CameraMode, int);
  ///@}

  ///@{
  /**
   * CAMERA_SCENE_VIEW: the view of the scene (0-based). Default 0.
   */
  vtkSetClampMacro(ViewIndex, int, 0, VTK_INT_MAX);
  vtkGetMacro(ViewIndex, int);
  ///@}

  ///@{
  /**
   * CAMERA_EXPLICIT: fx, fy, cx, cy relative to the image size. Default (1, 1, 0.5, 0.5).
   */
  vtkSetVector4Macro(Intrinsics, double);
  vtkGetVector4Macro(Intrinsics, double);
  ///@}

  ///@{
  /**
   * CAMERA_EXPLICIT: world->camera [R | t], 3 x 4 row-major. Default identity.
   */
  void SetExtrinsics(const double e[12]);
  void SetExtrinsics(double r00, double r01, double r02, double t0, double r10, double r11,
                     double r12, double t1, double r20, double r21, double r22, double t2);
  vtkGetVectorMacro(Extrinsics, double, 12);
  ///@}

  ///@{
  /**
   * CAMERA_EXPLICIT: the camera's image size; (0, 0) = the MLI's. Default (0, 0).
   */
  vtkSetVector2Macro(ImageSize, int);
  vtkGetVector2Macro(ImageSize, int);
  ///@}

  ///@{
  /**
   * CAMERA_TRAJECTORY: TRAJECTORY_SPIRAL (LLFF's spiral) or TRAJECTORY_ORBIT. Default spiral.
   */
  vtkSetClampMacro(TrajectoryType, int, TRAJECTORY_SPIRAL, TRAJECTORY_ORBIT);
  vtkGetMacro(TrajectoryType, int);
  ///@}

  ///@{
  /**
   * CAMERA_TRAJECTORY: frames of the path (>= 1) and the frame to render. Defaults 60, 0.
   */
  vtkSetClampMacro(NumberOfFrames, int, 1, VTK_INT_MAX);
  vtkGetMacro(NumberOfFrames, int);
  vtkSetClampMacro(FrameIndex, int, 0, VTK_INT_MAX);
  vtkGetMacro(FrameIndex, int);
  ///@}

  ///@{
  /**
   * CAMERA_TRAJECTORY: path radii along the reference camera's x, y, z; (0, 0, 0) = automatic.
   */
  vtkSetVector3Macro(TrajectoryRadii, double);
  vtkGetVector3Macro(TrajectoryRadii, double);
  ///@}

  ///@{
  /**
   * CAMERA_TRAJECTORY: reference-camera depth of the look-at point; 0 = automatic.
   */
  vtkSetClampMacro(FocusDepth, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(FocusDepth, double);
  ///@}

  ///@{
  /**
   * Output size in pixels; 0 = the camera's own (see the class description). Default 0, 0.
   */
  vtkSetClampMacro(Width, int, 0, 1 << 16);
  vtkGetMacro(Width, int);
  vtkSetClampMacro(Height, int, 0, 1 << 16);
  vtkGetMacro(Height, int);
  ///@}

  ///@{
  /**
   * SCREEN_LINEAR (default, the reference's) or PERSPECTIVE_CORRECT interpolation.
   */
  vtkSetClampMacro(Interpolation, int, SCREEN_LINEAR, PERSPECTIVE_CORRECT);
  vtkGetMacro(Interpolation, int);
  ///@}

  ///@{
  /**
   * Fragments kept per pixel, 1..64. Default 16 (the reference's peeling passes).
   */
  vtkSetClampMacro(MaxFragments, int, 1, 64);
  vtkGetMacro(MaxFragments, int);
  ///@}

protected:
  vtkSIMPLIRenderView();
  ~vtkSIMPLIRenderView() override = default;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestInformation(vtkInformation* request, vtkInformationVector** inputVector,
                         vtkInformationVector* outputVector) override;
  int RequestUpdateExtent(vtkInformation* request, vtkInformationVector** inputVector,
                          vtkInformationVector* outputVector) override;
  int RequestData(vtkInformation* request, vtkInformationVector** inputVector,
                  vtkInformationVector* outputVector) override;

  // The output size for RequestInformation when Width and Height do not fix it: updates the
  // inputs (the size is a property of their data: the MLI's or the scene view's camera) and
  // reads their cameras. False when that fails (RequestData then reports the error).
  bool PredictOutputSize(int size[2]);

  int CameraMode = CAMERA_REFERENCE;
  int ViewIndex = 0;
  double Intrinsics[4] = {1.0, 1.0, 0.5, 0.5};
  double Extrinsics[12] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
  int ImageSize[2] = {0, 0};
  int TrajectoryType = TRAJECTORY_SPIRAL;
  int NumberOfFrames = 60;
  int FrameIndex = 0;
  double TrajectoryRadii[3] = {0.0, 0.0, 0.0};
  double FocusDepth = 0.0;
  int Width = 0;
  int Height = 0;
  int Interpolation = SCREEN_LINEAR;
  int MaxFragments = 16;

private:
  vtkSIMPLIRenderView(const vtkSIMPLIRenderView&) = delete;
  void operator=(const vtkSIMPLIRenderView&) = delete;
};

#endif
