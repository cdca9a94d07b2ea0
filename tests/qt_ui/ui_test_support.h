#pragma once
// Shared helpers of the window's tests: a mesh file made in code, waiting while Qt runs.
#include "mesh/generators.h"
#include "mesh/mesh_io.h"
#include <QApplication>
#include <QDir>
#include <QString>
#include <QTemporaryDir>
#include <chrono>
#include <memory>

namespace hbtest {

/// Processes events until `done()` or `seconds` pass; returns done().
template <class F>
bool waitFor(F done, double seconds = 120.0) {
  const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  while (!done()) {
    if (std::chrono::steady_clock::now() > until) return done();
    QApplication::processEvents(QEventLoop::AllEvents, 20);
  }
  return true;
}

inline void pump(double seconds) {
  waitFor([] { return false; }, seconds);
}

/// A temporary folder holding a bumpy sphere OFF (about 5K triangles).
struct MeshDir {
  QTemporaryDir dir;
  QString mesh;
  MeshDir() {
    hb::BumpySphereOptions o;
    o.radius = 50.f;
    o.subdivisions = 4;  // 5,120 triangles
    hb::TriangleMesh m = hb::make_bumpy_sphere(o);
    mesh = dir.filePath(QStringLiteral("bumpy.off"));
    hb::write_mesh(m, QFile::encodeName(mesh).toStdString());
    // The box cache (XDG convention) of the windows made while this directory lives: its own,
    // so no test sees another's bakes.
    qputenv("XDG_CACHE_HOME", QFile::encodeName(dir.filePath(QStringLiteral("xdg-cache"))));
  }
};

}  // namespace hbtest
