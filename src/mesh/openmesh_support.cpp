// OpenMesh glue shared by the OM reader and the writers: the process-wide OpenMesh lock, and
// OpenMeshChatterCapture (OpenMesh's omerr() text becomes warnings instead of std::cerr).
#include <OpenMesh/Core/IO/MeshIO.hh>  // must precede the mesh kernel headers
#include <OpenMesh/Core/System/omstream.hh>

#include "mesh/openmesh_support.h"
#include "mesh/text_tokens.h"

#include <algorithm>
#include <iostream>
#include <utility>

namespace hb::detail {

std::mutex& openmesh_mutex() {
  static std::mutex m;
  return m;
}

OpenMeshChatterCapture::OpenMeshChatterCapture() {
  err_was_enabled_ = omerr().is_enabled();
  out_was_enabled_ = omout().is_enabled();
  log_was_enabled_ = omlog().is_enabled();
  had_cerr_ = omerr().disconnect(std::cerr);
  omerr().connect(captured_);
  omerr().enable();
  omout().disable();
  omlog().disable();
}

OpenMeshChatterCapture::~OpenMeshChatterCapture() {
  omerr().flush();
  omerr().disconnect(captured_);
  if (had_cerr_) omerr().connect(std::cerr);
  if (!err_was_enabled_) omerr().disable();
  if (out_was_enabled_) omout().enable();
  if (log_was_enabled_) omlog().enable();
}

std::vector<std::string> OpenMeshChatterCapture::lines() {
  omerr().flush();
  std::vector<std::pair<std::string, std::size_t>> seen;
  std::istringstream in(captured_.str());
  std::string l;
  while (std::getline(in, l)) {
    l = std::string(LineReader::trim(l));
    if (l.empty()) continue;
    auto it = std::find_if(seen.begin(), seen.end(), [&](const auto& p) { return p.first == l; });
    if (it == seen.end()) seen.emplace_back(l, 1);
    else ++it->second;
  }
  std::vector<std::string> out;
  for (const auto& [text, n] : seen)
    out.push_back(n > 1 ? text + " (x" + std::to_string(n) + ")" : text);
  return out;
}

} // namespace hb::detail
