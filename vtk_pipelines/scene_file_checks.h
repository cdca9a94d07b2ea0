#pragma once
// Scene files checked before Assimp opens them: Assimp trusts what a file declares (sizes,
// counts, indices, transforms) and crashes, hangs or reads another mesh when it lies. Each
// check throws hb::InvalidInput naming the file and what it holds against what it declares.
#include <string>

namespace hb::vtk {

/// glTF (.gltf) or, with `binary`, GLB: the JSON and its buffers (formats/gltf_check.h); an
/// external buffer file must exist.
void check_gltf(const std::string& path, bool binary);
/// 3MF: the zip's entries (sizes, CRC-32, at most 1 GB inflated), the root relationship and its
/// model part, every transform of 12 numbers, no component containing itself, every vertex's
/// x, y, z a decimal number (no hex, no text, none missing), every triangle's corners naming
/// vertices of its mesh.
void check_3mf(const std::string& path);
/// ASCII FBX: every array holds the values it declares; polygon indices refer to vertices.
void check_fbx(const std::string& path);
/// Collada: float_array counts, accessors reading their arrays whole (offset + count x stride,
/// stride holding the params), polygon lists of the declared sizes, indices within the largest
/// array, a node graph (nesting and instancing) without cycles, of bounded depth and expansion.
void check_collada(const std::string& path);

/// The unit of a 3MF model (its <model unit="..."> attribute; millimetre when absent) as a name
/// load_model knows; `source` says where it was read. Throws hb::InvalidInput for an unknown unit.
std::string three_mf_unit(const std::string& path, std::string& source);

} // namespace hb::vtk
