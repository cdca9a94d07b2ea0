#pragma once
// Collects a VTK algorithm's error messages (and keeps them off the console) so that a reader
// can rethrow them with the file's name.
#include <vtkCallbackCommand.h>
#include <vtkNew.h>
#include <string>

class vtkObject;

namespace hb::vtk {

/// Observes `watched`'s ErrorEvent for its own lifetime.
class ErrorCatcher {
public:
  explicit ErrorCatcher(vtkObject* watched);
  ~ErrorCatcher();
  ErrorCatcher(const ErrorCatcher&) = delete;
  ErrorCatcher& operator=(const ErrorCatcher&) = delete;
  /// The messages' texts joined by "; " (VTK's "ERROR: In file, line N\nclass (ptr): " prefix
  /// dropped, repeats removed); never empty.
  std::string message() const;
  bool failed() const { return !messages_.empty(); }

private:
  vtkObject* watched_;
  vtkNew<vtkCallbackCommand> callback_;
  unsigned long tag_ = 0;
  std::string messages_;
};

} // namespace hb::vtk
