#pragma once
// glTF 2.0 (.gltf, .glb) checked before Assimp reads it: the GLB container's chunk lengths,
// and in the JSON the node graph (indices in range, no cycle, no node with two parents, depth
// bounded: Assimp recurses once a level) and every accessor, buffer view and buffer against
// the bytes that back it (Assimp trusts the lengths and reads or allocates what they say).
// Pure functions over bytes (no file access): the fuzz targets run them under the sanitizers.
#include <cstdint>
#include <functional>
#include <string>

namespace hb {

/// Deepest node nesting accepted (a scene graph a person made is far shallower).
constexpr int kMaxGltfDepth = 256;

/// A GLB file's container: the 12-byte header (magic "glTF", version 2, total length equal to
/// the file's), a JSON chunk first and at most one BIN chunk, each length within the file.
/// Returns the JSON chunk's text; `bin_bytes` is the BIN chunk's length (0 without one).
/// Throws hb::InvalidInput naming `name` and the field.
std::string check_glb(const std::string& name, const std::string& bytes, std::uint64_t& bin_bytes);

/// A glTF JSON document. `external_bytes(uri)` gives the size of a buffer stored in a file
/// beside the document (uri as written; it throws or returns the size); a buffer without a uri
/// is the GLB's BIN chunk of `bin_bytes`; "data:" URIs are measured here. Throws
/// hb::InvalidInput naming `name` and what is wrong (not JSON, a node cycle, an accessor past
/// its buffer view...).
void check_gltf_json(const std::string& name, const std::string& json, std::uint64_t bin_bytes,
                     const std::function<std::uint64_t(const std::string& uri)>& external_bytes);

} // namespace hb
