#pragma once
// The .hbox file format, version 9 (little-endian; versions 1 to 8 are still read):
//  1. Header: magic "HBOXFILE", u32 version, u32 box count, u64 mesh hash, u64 triangles,
//     f32 diagonal, u32 path length + path bytes; then per box: u32 codec (CodecId: 0 raw
//     8-byte samples, 1 Haar, 2 block), i32 m, i32 n, f32 centre[3], axes[9] (columns),
//     half[3], u64 table offset, u64 table bytes, u64 table hash (xxHash3 64); version 2 adds
//     the codec statistics: f32 error bound, mean and max t error (relative to the box
//     diagonal), mean and max normal angle (degrees), u64 hit/miss flips; version 3 adds
//     the box's triangle ids (u64 offset, u64 bytes: 0 without refinement, 2 or 4 a sample;
//     u64 hash; u32 base added to 2-byte ids, see TriangleIds) and,
//     after the boxes, the scene's surface triangles (u64 offset, u64 bytes, u64 hash);
//     version 4 adds the scene's piece ids (u64 offset, u64 bytes: 0 or 4 a triangle of the
//     source mesh, u64 hash; BoxScene::piece_of_triangle); version 5 adds the scene grid (u64
//     offset, u64 bytes: 0 without one, u64 hash; its bytes: SceneGrid::serialize); version 6
//     adds the budget report (u64 offset, u64 bytes: 0 for a scene not baked to a budget,
//     u64 hash; its bytes: BudgetReport::serialize, key=value text); version 7 adds the
//     surface's normal map (u32 side: 0 without one, u64 offset, u64 bytes, u64 hash; its
//     bytes: u32 octahedral codes, SurfaceTriangles::set_normal_map); version 8 lets a box
//     hold no table (table offset, bytes and hash 0, codec 0, no triangle ids: a frame,
//     HapticBox::frame; its scene answered by exact Embree, BoxScene::without_tables) and is
//     written only when a box does (every other file is written as version 7, byte for byte
//     as before); version 9 adds the stroke route's full mesh (u64 offset, u64 bytes, u64
//     hash; its bytes: u32 vertex count V, u32 triangle count T, V f32 positions xyz, V f32
//     unit vertex normals xyz, T u32 vertex index triples; SceneParts::stroke) and is
//     written only when a scene has one; then u64 hash of all header bytes before it.
//  2. Tables at 64-byte aligned offsets: raw records in BoxLayout::sample_index order (box_layout.h), or a
//     compressed payload (codec/table_payload.h); then each refined box's triangle ids
//     (same order; u16 offsets or u32 slots), then the SurfaceTriangles records, then the
//     piece ids (u32 per triangle), then the scene grid, then the budget report, then the
//     normal map, then the stroke mesh.
//  3. Loading (box_file_load.cpp) maps the file and checks what the query trusts.
// The constants both sides of the format share (box_file.cpp writes, box_file_load.cpp reads).
#include <cstddef>
#include <cstdint>

namespace hb {

constexpr char kBoxFileMagic[8] = {'H', 'B', 'O', 'X', 'F', 'I', 'L', 'E'};
constexpr std::uint32_t kBoxFileVersion = 9;
/// The version of a file whose boxes all hold tables (version 8 adds only frames).
constexpr std::uint32_t kBoxFileVersionWithTables = 7;
/// The version of a file with frames and no stroke mesh (version 9 adds only that mesh).
constexpr std::uint32_t kBoxFileVersionWithFrames = 8;
/// Every section starts at a multiple of this.
constexpr std::size_t kBoxFileAlign = 64;

} // namespace hb
