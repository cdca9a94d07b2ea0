// OFF reader: a strict line-based parser of our own, parallel over chunks of lines.
//
//  1. Refuse NUL bytes (binary OFF) and find the header keyword: [ST][C][N]OFF, or the counts
//     alone (some writers omit the keyword); 4OFF / nOFF (other dimensions) are refused.
//  2. Read 'vertices faces [edges]' (on the header line or the next one).
//  3. Cut the rest into chunks of whole lines (about 1 MB) and count each chunk's content
//     lines and physical lines in parallel; prefix sums give every content line its role
//     (vertex v, face f, or trailing and ignored) and every line its number, so the chunks
//     can then be parsed independently and errors still name the right line.
//  4. Check the declared counts against the content lines present before reserving anything,
//     so an absurd header cannot trigger a huge allocation or a long loop.
//  5. Count the corners of the faces each chunk holds (first token only), so that every
//     chunk writes its vertices, indices and face offsets straight into the soup at known
//     places: the result is the sequential reader's, element for element, with no per-chunk
//     buffers to merge.
//  6. Parse: vertices 3 numbers each (extra values ignored); faces a corner count then that
//     many indices in range (a colour after them ignored). Each chunk keeps its first error;
//     the error of the earliest chunk is thrown, which is the first in the file, as a
//     sequential read would report.
// Every pass gives its chunks' pages back as it goes (MappedFile::release), so the file is
// never resident as a whole next to the soup.
#include "mesh/mapped_file.h"
#include "mesh/mesh_readers.h"
#include "mesh/text_tokens.h"

#include "errors.h"
#include "formats/quoted_text.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <cstdint>
#include <cstring>
#include <limits>
#include <optional>
#include <string_view>
#include <vector>

namespace hb::detail {
namespace {

/// Lines of about this many bytes make one chunk: large enough that a chunk's bookkeeping is
/// negligible, small enough for two threads to balance and for released pages to matter.
constexpr std::size_t kChunkBytes = std::size_t(1) << 20;

struct Chunk {
  std::size_t begin = 0, end = 0;  ///< byte range in the file: whole lines
  // Pass 1 (step 3)
  std::size_t content_lines = 0;
  std::size_t physical_lines = 0;
  // Prefix sums
  std::size_t first_content = 0;   ///< index of its first content line after the header
  std::size_t line_before = 0;     ///< number of the line just before the chunk
  // Pass 2 (step 5)
  std::size_t corners = 0;         ///< indices it stores (faces with 3 or more corners)
  std::size_t faces_kept = 0;      ///< faces with 3 or more corners
  std::size_t first_corner = 0, first_kept = 0;
  // Pass 3 (step 6)
  std::size_t short_faces = 0;
  std::optional<std::size_t> error_line;
  std::string error;
};

/// Cuts [begin, text.size()) into chunks ending just after a '\n' (the last at the end).
std::vector<Chunk> cut_chunks(std::string_view text, std::size_t begin) {
  std::vector<Chunk> chunks;
  while (begin < text.size()) {
    std::size_t end = begin + kChunkBytes;
    if (end >= text.size()) {
      end = text.size();
    } else {
      const void* nl = std::memchr(text.data() + end, '\n', text.size() - end);
      end = nl ? std::size_t(static_cast<const char*>(nl) - text.data()) + 1 : text.size();
    }
    Chunk c;
    c.begin = begin;
    c.end = end;
    chunks.push_back(c);
    begin = end;
  }
  return chunks;
}

template <typename Body>
void for_each_chunk(std::vector<Chunk>& chunks, const Body& body) {
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, chunks.size()), [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t i = r.begin(); i != r.end(); ++i) body(chunks[i]);
  });
}

InvalidInput off_error(const std::string& path, std::size_t line, const std::string& cause) {
  return InvalidInput(path + ":" + std::to_string(line) + ": " + cause);
}

// Steps 1-2: the header keyword ([ST][C][N]OFF; "4OFF"/"nOFF" (other dimensions) and binary
// are refused) and the counts 'vertices faces [edges]', on the header line or the next one.
std::vector<long long> read_off_counts(const std::string& path, LineReader& lines) {
  std::string_view line;
  if (!lines.next(line)) throw IoError(path + ": file has no content (only blanks or comments)");
  Tokens head(line);
  std::string_view tok;
  head.next(tok);
  std::vector<long long> counts;
  const std::string key(tok);
  const bool keyword = key.size() >= 3 && key.compare(key.size() - 3, 3, "OFF") == 0;
  if (keyword) {
    const std::string prefix = key.substr(0, key.size() - 3);
    if (prefix.find('4') != std::string::npos || prefix.find('n') != std::string::npos)
      throw off_error(path, lines.line_number(), "OFF variant '" + quoted_text(key, 40) + "' (not 3D) is not supported");
    for (char c : prefix)
      if (c != 'S' && c != 'T' && c != 'C' && c != 'N')
        throw off_error(path, lines.line_number(), "unrecognised OFF header '" + quoted_text(key, 40) + "'");
  } else {
    // Some writers omit the keyword; then the first line must be the counts.
    long long v;
    if (!parse_number(tok, v))
      throw off_error(path, lines.line_number(), "not an OFF file (header '" + quoted_text(key, 40) + "')");
    counts.push_back(v);
  }
  while (head.next(tok)) {
    long long v;
    if (tok == "BINARY") throw off_error(path, lines.line_number(), "binary OFF is not supported");
    if (!parse_number(tok, v)) throw off_error(path, lines.line_number(), "bad count '" + quoted_text(std::string(tok), 40) + "'");
    counts.push_back(v);
  }
  if (counts.empty()) {  // counts on their own line
    if (!lines.next(line)) throw IoError(path + ": truncated after the OFF header (no counts)");
    Tokens t(line);
    while (t.next(tok)) {
      long long v;
      if (!parse_number(tok, v)) throw off_error(path, lines.line_number(), "bad count '" + quoted_text(std::string(tok), 40) + "'");
      counts.push_back(v);
    }
  }
  if (counts.size() < 2 || counts.size() > 3)
    throw off_error(path, lines.line_number(), "expected 'vertices faces [edges]' counts");
  if (counts[0] < 0 || counts[1] < 0) throw off_error(path, lines.line_number(), "negative vertex or face count");
  return counts;
}

// Step 3: each chunk's content and physical lines counted in parallel, then their prefix
// sums (the header ends at line `header_lines`). Returns the content lines after the header.
std::size_t count_off_lines(std::vector<Chunk>& chunks, std::string_view text, const MappedFile& file,
                            std::size_t header_lines) {
  for_each_chunk(chunks, [&](Chunk& c) {
    LineReader r(text.substr(c.begin, c.end - c.begin));
    std::string_view l;
    while (r.next(l)) ++c.content_lines;
    c.physical_lines = r.line_number();
    // Released after every pass: the soup is allocated in between, and the file's pages
    // should not be resident next to it (they fault back in from the page cache).
    file.release(c.begin, c.end);
  });
  std::size_t available = 0, line_number = header_lines;
  for (Chunk& c : chunks) {
    c.first_content = available;
    c.line_before = line_number;
    available += c.content_lines;
    line_number += c.physical_lines;
  }
  return available;
}

// A face line's corner count (its first token), when it parses and fits the line.
bool off_corner_count(std::string_view face_line, long long& k) {
  Tokens t(face_line);
  std::string_view first;
  return t.next(first) && parse_number(first, k) && k >= 0 && static_cast<unsigned long long>(k) <= face_line.size();
}

// Step 5: the corners and kept faces each chunk stores, and where they start. A face line that
// does not parse counts nothing here; step 6 stops its chunk at that line with the error,
// before writing anything of it.
void count_off_corners(std::vector<Chunk>& chunks, std::string_view text, const MappedFile& file, std::size_t n_vertices,
                       std::size_t n_lines) {
  for_each_chunk(chunks, [&](Chunk& c) {
    if (c.first_content + c.content_lines <= n_vertices) return;
    LineReader r(text.substr(c.begin, c.end - c.begin));
    std::string_view l;
    for (std::size_t g = c.first_content; g < n_lines && r.next(l); ++g) {
      long long k;
      if (g < n_vertices || !off_corner_count(l, k) || k < 3) continue;
      c.corners += std::size_t(k);
      ++c.faces_kept;
    }
    file.release(c.begin, c.end);
  });
  std::size_t corners = 0, kept = 0;
  for (Chunk& c : chunks) {
    c.first_corner = corners;
    c.first_kept = kept;
    corners += c.corners;
    kept += c.faces_kept;
  }
}

// One vertex line: 3 numbers (extra values, normals, colours, texture coordinates, are
// ignored). Empty, or the error.
std::string parse_off_vertex(Tokens& t, std::size_t v, PolygonSoup& soup) {
  std::string_view tok;
  double x[3];
  for (double& xi : x)
    if (!t.next(tok) || !parse_number(tok, xi)) return "vertex " + std::to_string(v) + ": expected 3 numeric coordinates";
  soup.positions[v] = Vec3(float(x[0]), float(x[1]), float(x[2]));
  return {};
}

// One face line: a corner count then that many indices in range (a colour after them is
// ignored); stored at `corner` when it has 3 corners or more (`stored` then true). Empty, or
// the error.
std::string parse_off_face(Tokens& t, std::string_view line, std::size_t f, std::size_t n_vertices, PolygonSoup& soup,
                           std::size_t corner, long long& k) {
  std::string_view tok;
  if (!t.next(tok) || !parse_number(tok, k) || k < 0) return "face " + std::to_string(f) + ": expected a corner count";
  if (static_cast<unsigned long long>(k) > line.size())  // each index needs >= 2 characters
    return "face " + std::to_string(f) + ": corner count " + std::to_string(k) + " exceeds the line";
  // Faces with fewer than 3 corners are checked but not stored (skipped, counted).
  const bool store = k >= 3;
  for (long long i = 0; i < k; ++i) {
    long long idx;
    if (!t.next(tok) || !parse_number(tok, idx))
      return "face " + std::to_string(f) + ": expected " + std::to_string(k) + " integer vertex indices";
    if (idx < 0 || idx >= static_cast<long long>(n_vertices))
      return "face " + std::to_string(f) + ": vertex index " + std::to_string(idx) + " out of range [0, " +
             std::to_string(n_vertices) + ")";
    if (store) soup.indices[corner + std::size_t(i)] = idx;
  }
  return {};
}

// Step 6: chunk c parses into its own places of the soup; its first error is kept.
void parse_off_chunk(Chunk& c, std::string_view text, std::size_t n_vertices, std::size_t n_lines, PolygonSoup& soup) {
  LineReader r(text.substr(c.begin, c.end - c.begin));
  std::string_view l;
  std::size_t corner = c.first_corner, face_kept = c.first_kept;
  for (std::size_t g = c.first_content; g < n_lines && r.next(l); ++g) {
    Tokens t(l);
    long long k = 0;
    std::string error = g < n_vertices ? parse_off_vertex(t, g, soup)
                                       : parse_off_face(t, l, g - n_vertices, n_vertices, soup, corner, k);
    if (!error.empty()) {
      c.error_line = c.line_before + r.line_number();
      c.error = std::move(error);
      break;
    }
    if (g < n_vertices) continue;
    if (k < 3) {
      ++c.short_faces;
      continue;
    }
    corner += std::size_t(k);
    soup.offsets[++face_kept] = corner;
  }
}

} // namespace

PolygonSoup read_off(const std::string& path, const MappedFile& file, MeshReadReport& report) {
  const std::string_view text = file.text();
  if (std::memchr(text.data(), '\0', text.size()))
    throw InvalidInput(path + ": not a text OFF file (contains NUL bytes; binary OFF is not supported)");
  LineReader lines(text);
  const std::vector<long long> counts = read_off_counts(path, lines);

  std::vector<Chunk> chunks = cut_chunks(text, lines.position());
  const std::size_t available = count_off_lines(chunks, text, file, lines.line_number());

  // Step 4: the declared counts against the lines present, before reserving anything.
  const auto n_vertices = static_cast<std::size_t>(counts[0]);
  const auto n_faces = static_cast<std::size_t>(counts[1]);
  if (n_vertices > std::numeric_limits<std::uint32_t>::max())
    throw off_error(path, lines.line_number(), "vertex count " + std::to_string(n_vertices) + " is too large");
  if (n_vertices > available || n_faces > available - n_vertices)
    throw IoError(path + ": truncated: header declares " + std::to_string(n_vertices) + " vertices and " +
                  std::to_string(n_faces) + " faces but only " + std::to_string(available) +
                  " data lines follow");
  report.input_vertices = n_vertices;
  report.input_faces = n_faces;
  const std::size_t n_lines = n_vertices + n_faces;  // content lines read; any after: ignored
  // Only the chunks that hold a vertex or a face line take part from here on.
  while (!chunks.empty() && chunks.back().first_content >= n_lines) chunks.pop_back();

  count_off_corners(chunks, text, file, n_vertices, n_lines);
  PolygonSoup soup;
  soup.positions.resize(n_vertices);
  soup.indices.resize(chunks.empty() ? 0 : chunks.back().first_corner + chunks.back().corners);
  soup.offsets.resize((chunks.empty() ? 0 : chunks.back().first_kept + chunks.back().faces_kept) + 1);
  soup.offsets[0] = 0;
  for_each_chunk(chunks, [&](Chunk& c) {
    parse_off_chunk(c, text, n_vertices, n_lines, soup);
    file.release(c.begin, c.end);
  });
  for (const Chunk& c : chunks) {
    if (c.error_line) throw off_error(path, *c.error_line, c.error);
    soup.short_faces += c.short_faces;
  }
  return soup;
}

} // namespace hb::detail
