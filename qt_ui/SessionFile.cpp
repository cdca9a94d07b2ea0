#include "SessionFile.h"
#include "errors.h"
#include "formats/quoted_text.h"
#include <QDir>
#include <QFile>
#include <QFileInfo>
#include <nlohmann/json.hpp>
#include <algorithm>
#include <cmath>
#include <fstream>

namespace {
std::string local(const QString& s) { return QFile::encodeName(s).toStdString(); }

// A file that reads as a session whatever its name: JSON whose start names the session format.
bool holdsSession(const QString& path) {
  std::ifstream in(local(path), std::ios::binary);
  if (!in) return false;
  std::string head(4096, '\0');
  in.read(head.data(), std::streamsize(head.size()));
  head.resize(std::size_t(in.gcount()));
  const std::size_t first = head.find_first_not_of(" \t\r\n");
  return first != std::string::npos && head[first] == '{' && head.find("\"hapticbox-session\"") != std::string::npos;
}
}  // namespace

bool isSessionPath(const QString& path) { return path.endsWith(QLatin1String(".hbsession"), Qt::CaseInsensitive); }

void saveSessionFile(const SessionState& s, const QString& path) {
  nlohmann::json j;
  j["format"] = "hapticbox-session";
  j["version"] = 1;
  j["mesh"] = s.meshPath.toStdString();
  j["bake"] = {{"recipe", s.bake.advanced ? "advanced" : "default"},
               {"m", s.bake.m},
               {"n", s.bake.n},
               {"padding", s.bake.padding},
               {"pieces", s.bake.pieces == BakeSettings::Pieces::None   ? "none"
                          : s.bake.pieces == BakeSettings::Pieces::File ? "file"
                                                                        : "auto"},
               {"pieces_file", s.bake.piecesFile.toStdString()},
               {"codec", s.bake.codec.toStdString()},
               {"refine", s.bake.refine},
               {"cache", s.bake.useCache},
               {"baked", s.baked}};
  j["probe"] = {{"depth_fraction", s.depthFraction},
                {"direction", {s.probeDirection[0], s.probeDirection[1], s.probeDirection[2]}},
                {"tilt_degrees", s.tiltDegrees}};
  if (s.hasProbe) j["probe"]["surface_point"] = {s.probePoint[0], s.probePoint[1], s.probePoint[2]};
  j["display"] = {{"outlines", s.outlines},
                  {"error_field", s.showErrorField},
                  {"metric", HapticSession::errorArrayName(s.metric)}};
  if (s.hasCamera)
    j["camera"] = {{"position", s.camera.position},
                   {"focal_point", s.camera.focalPoint},
                   {"view_up", s.camera.viewUp},
                   {"view_angle", s.camera.viewAngle},
                   {"parallel_scale", s.camera.parallelScale}};
  if (s.hasSurface) {
    nlohmann::json v = {{"smooth_iterations", s.surface.smooth_iterations},
                        {"target_triangles", s.surface.target_triangles}};
    v["iso"] = s.surface.iso ? nlohmann::json(*s.surface.iso) : nlohmann::json();  // null: automatic (Otsu)
    v["label"] = s.surface.label ? nlohmann::json(*s.surface.label) : nlohmann::json();
    j["surface"] = v;
  }
  std::ofstream out(local(path));
  out << j.dump(2) << "\n";
  if (!out) throw hb::IoError(local(path) + ": cannot write the session file");
}

SessionState loadSessionFile(const QString& path) {
  std::ifstream in(local(path));
  if (!in) throw hb::IoError(local(path) + ": cannot open the session file");
  SessionState s;
  try {
    const nlohmann::json j = nlohmann::json::parse(in);
    if (j.value("format", "") != "hapticbox-session")
      throw hb::InvalidInput(local(path) + ": not a HapticBox session file");
    const QDir base = QFileInfo(path).absoluteDir();
    s.meshPath = QDir::cleanPath(base.absoluteFilePath(QString::fromStdString(j.at("mesh").get<std::string>())));
    // A session names a model. One that names a session (itself, another, a cycle of them)
    // would have the window open sessions without end: refused here, before anything opens.
    const bool self = QFileInfo(s.meshPath).canonicalFilePath() == QFileInfo(path).canonicalFilePath();
    if (self || isSessionPath(s.meshPath) || holdsSession(s.meshPath))
      throw hb::InvalidInput(local(path) + ": \"mesh\" names " +
                             (self ? std::string("this session file itself")
                                   : "the session file " + hb::quoted_text(local(s.meshPath), 200)) +
                             ", not a model (a session opens a model; it cannot open a session)");
    const auto& b = j.at("bake");
    // Session files from before the default recipe name an explicit sampling.
    s.bake.advanced = b.value("recipe", std::string("advanced")) != "default";
    s.bake.m = b.value("m", 16);
    s.bake.n = b.value("n", 8);
    s.bake.padding = b.value("padding", 0.01f);
    const std::string pieces = b.value("pieces", "none");
    s.bake.pieces = pieces == "file" ? BakeSettings::Pieces::File
                    : pieces == "auto" ? BakeSettings::Pieces::Automatic
                                       : BakeSettings::Pieces::None;
    const std::string pf = b.value("pieces_file", "");
    if (!pf.empty()) s.bake.piecesFile = QDir::cleanPath(base.absoluteFilePath(QString::fromStdString(pf)));
    s.bake.codec = QString::fromStdString(b.value("codec", "none"));
    s.bake.refine = b.value("refine", false);
    s.bake.useCache = b.value("cache", true);
    s.baked = b.value("baked", false);
    if (j.contains("probe")) {
      const auto& p = j["probe"];
      s.depthFraction = p.value("depth_fraction", 0.01);
      if (p.contains("direction")) s.probeDirection = p["direction"].get<std::array<float, 3>>();
      s.tiltDegrees = p.value("tilt_degrees", 0.0);
      if (p.contains("surface_point")) {
        s.probePoint = p["surface_point"].get<std::array<float, 3>>();
        s.hasProbe = std::all_of(s.probePoint.begin(), s.probePoint.end(), [](float v) { return std::isfinite(v); });
        if (!s.hasProbe) throw hb::InvalidInput(local(path) + ": probe.surface_point is not finite");
      }
    }
    if (j.contains("display")) {
      const auto& d = j["display"];
      s.outlines = d.value("outlines", false);
      s.showErrorField = d.value("error_field", false);
      const std::string m = d.value("metric", "PerceptibleRatio");
      for (ErrorMetric e : kErrorMetrics)
        if (m == HapticSession::errorArrayName(e)) s.metric = e;
    }
    if (j.contains("camera")) {
      const auto& c = j["camera"];
      s.hasCamera = true;
      s.camera.position = c.at("position").get<std::array<double, 3>>();
      s.camera.focalPoint = c.at("focal_point").get<std::array<double, 3>>();
      s.camera.viewUp = c.at("view_up").get<std::array<double, 3>>();
      s.camera.viewAngle = c.value("view_angle", 30.0);
      s.camera.parallelScale = c.value("parallel_scale", 1.0);
    }
    if (j.contains("surface")) {
      const auto& v = j["surface"];
      s.hasSurface = true;
      if (v.contains("iso") && !v["iso"].is_null()) {
        s.surface.iso = v["iso"].get<double>();
        if (!std::isfinite(*s.surface.iso)) throw hb::InvalidInput(local(path) + ": surface.iso is not a finite number");
      }
      if (v.contains("label") && !v["label"].is_null()) s.surface.label = v["label"].get<long>();
      if (s.surface.iso && s.surface.label)
        throw hb::InvalidInput(local(path) + ": surface gives both an iso-value and a label (one or the other)");
      s.surface.smooth_iterations = v.value("smooth_iterations", 0);
      if (s.surface.smooth_iterations < 0)
        throw hb::InvalidInput(local(path) + ": surface.smooth_iterations is negative");
      s.surface.target_triangles = v.value("target_triangles", std::size_t(0));
    }
  } catch (const nlohmann::json::exception& e) {
    throw hb::InvalidInput(local(path) + ": not a valid session file (" + e.what() + ")");
  }
  return s;
}
