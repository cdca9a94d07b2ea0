#include "vtk_error_catcher.h"
#include <vtkCommand.h>
#include <vtkObject.h>
#include <cctype>

namespace hb::vtk {

ErrorCatcher::ErrorCatcher(vtkObject* watched) : watched_(watched) {
  callback_->SetClientData(this);
  callback_->SetCallback([](vtkObject*, unsigned long, void* client, void* call) {
    auto* self = static_cast<ErrorCatcher*>(client);
    if (call) self->messages_ += (self->messages_.empty() ? "" : "; ") + std::string(static_cast<const char*>(call));
  });
  tag_ = watched_->AddObserver(vtkCommand::ErrorEvent, callback_);
}

ErrorCatcher::~ErrorCatcher() { watched_->RemoveObserver(tag_); }

// VTK's messages read "ERROR: In file, line N\nclass (ptr): text\n\n", one after another:
// keep the text of each (never an empty cause: the raw message when nothing is left).
std::string ErrorCatcher::message() const {
  std::string out;
  std::size_t at = 0;
  while (at < messages_.size()) {
    std::size_t next = messages_.find("; ERROR: ", at);
    std::string m = messages_.substr(at, next == std::string::npos ? std::string::npos : next - at);
    at = next == std::string::npos ? messages_.size() : next + 2;
    if (m.rfind("ERROR: In ", 0) == 0) {
      const std::size_t nl = m.find('\n');
      if (nl != std::string::npos) m = m.substr(nl + 1);
    }
    const std::size_t colon = m.find("): ");
    if (colon != std::string::npos && colon < 80) m = m.substr(colon + 3);
    for (char& c : m)
      if (c == '\n' || c == '\r') c = ' ';
    while (!m.empty() && std::isspace((unsigned char)m.back())) m.pop_back();
    while (!m.empty() && std::isspace((unsigned char)m.front())) m.erase(0, 1);
    if (m.empty() || out.find(m) != std::string::npos) continue;
    out += (out.empty() ? "" : "; ") + m;
  }
  if (out.empty()) out = "the VTK reader reported an error without a reason";
  return out;
}

} // namespace hb::vtk
