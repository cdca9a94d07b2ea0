#pragma once
// glTF 2.0 (.gltf, .glb) checked before Assimp reads it: the GLB container's chunk lengths,
// and in the JSON the node graph (indices in range, no cycle, no node with two parents, depth
// bounded: Assimp recurses once a level) and every accessor, buffer view and buffer against
// the bytes that back it (Assimp trusts the lengths and reads or allocates what they say);
// then the data a mesh is made of: POSITION accessors of three floats within their declared
// min and max, index accessors of unsigned integers naming existing vertices (Assimp dropped
// a triangle with an index out of range without a word, and read a POSITION of another type
// as floats), sparse accessors within their accessor.
// Pure functions over bytes (no file access): the fuzz targets run them under the sanitizers.
#include <cstdint>
#include <functional>
#include <string>
#include <string_view>

namespace hb {

/// Deepest node nesting accepted (a scene graph a person made is far shallower).
constexpr int kMaxGltfDepth = 256;

/// A GLB file's container: the 12-byte header (magic "glTF", version 2, total length equal to
/// the file's), a JSON chunk first and at most one BIN chunk, each length within the file.
/// Returns the JSON chunk's text; `bin` is the BIN chunk's bytes within `bytes` (empty without
/// one). Throws hb::InvalidInput naming `name` and the field.
std::string check_glb(const std::string& name, const std::string& bytes, std::string_view& bin);

/// A glTF JSON document. `external_data(uri)` gives the bytes of a buffer stored in a file
/// beside the document (uri as written; it throws, or returns a view the caller keeps alive
/// until this returns); a buffer without a uri is the GLB's BIN chunk `bin`; "data:" URIs are
/// decoded here. Throws hb::InvalidInput naming `name` and what is wrong (not JSON, a node
/// cycle, an accessor past its buffer view, an index past the vertices...).
void check_gltf_json(const std::string& name, const std::string& json, std::string_view bin,
                     const std::function<std::string_view(const std::string& uri)>& external_data);

} // namespace hb
