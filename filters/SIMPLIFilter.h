// What every SIMPLI filter's RequestData shares, written once (the role of TTK's ttkAlgorithm):
// turning the model's exceptions into vtkErrorMacro and a failed request, progress and abort,
// and the choice of the OpenCL device. Private to the module (PRIVATE_HEADERS).
//
// The filters derive from five VTK bases (vtkPartitionedDataSetCollectionAlgorithm,
// vtkTableAlgorithm, vtkPolyDataAlgorithm, vtkImageAlgorithm, vtkWriter) whose pipeline
// behaviour they rely on, and VTK's wrappers cannot take a class template as a base, so this is
// a helper every RequestData calls rather than one more base class:
//
//   int vtkSIMPLIX::RequestData(...) {
//     return simpli::vtkfilter::runRequest(this, "SIMPLI X", [&](const Progress& progress) {
//       ... read inputs, call model/, fill outputs; progress(f) is false once aborted ...
//     }, [&] { output->Initialize(); });
//   }
//
// The model keeps one process-wide device (simpli/ocl/device.h) and re-selecting it destroys
// the old one, so every tensor of the old device must be gone first. Filters that keep tensors
// between updates (vtkSIMPLIBuildMLI's cached network) register a release callback here;
// selectDevice runs them all before it changes the device.
#pragma once

#include <functional>
#include <string>

class vtkAlgorithm;

namespace simpli::vtkfilter {

/// Progress and abort of one request: the algorithm's progress bar over [begin, end].
class Progress {
public:
  explicit Progress(vtkAlgorithm* algorithm, double begin = 0.0, double end = 1.0)
      : algorithm_(algorithm), begin_(begin), end_(end) {}
  /// Reports the fraction f (0..1) of this range done; false when the user aborted.
  bool operator()(double f) const;
  /// True when the user aborted the request (AbortExecute).
  bool aborted() const;
  /// The part [a, b] (fractions of this range) as its own Progress.
  Progress range(double a, double b) const {
    return Progress(algorithm_, begin_ + a * (end_ - begin_), begin_ + b * (end_ - begin_));
  }

private:
  vtkAlgorithm* algorithm_;
  double begin_, end_;
};

/// Runs `body`, a request's work, and returns the request's result: 1 when it returns (also
/// when it stopped early because the user aborted), 0 when it throws. A simpli::Error becomes
/// vtkErrorMacro "<what>: <message>", any other exception "<what>: unexpected failure:
/// <message>"; `onFailure` (e.g. emptying the outputs) runs before 0 is returned. Warnings
/// (simpli/warning.h) raised by `body` become vtkWarningMacro "<what>: <message>".
int runRequest(vtkAlgorithm* algorithm, const std::string& what,
               const std::function<void(const Progress&)>& body,
               const std::function<void()>& onFailure = {});

/// Makes `selector` ("platform:device") the current OpenCL device; empty keeps the current
/// one. Nothing happens when it already is the current device. Throws simpli::Error naming
/// `property` and the value when it is malformed or the device does not exist.
void selectDevice(const std::string& selector, const std::string& property);

/// "p:d" of the current device (opens the default device when none is open yet).
std::string currentDevice();

/// Registers `release`, called before the device changes; returns a handle for
/// unregisterDeviceUser.
int registerDeviceUser(std::function<void()> release);
void unregisterDeviceUser(int handle);

/// A VTK string property as a std::string ("" for null).
inline std::string str(const char* s) {
  return s ? std::string(s) : std::string();
}

} // namespace simpli::vtkfilter
