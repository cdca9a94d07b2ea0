// OFF reader: a strict line-based parser of our own.
//
//  1. Refuse NUL bytes (binary OFF) and find the header keyword: [ST][C][N]OFF, or the counts
//     alone (some writers omit the keyword); 4OFF / nOFF (other dimensions) are refused.
//  2. Read 'vertices faces [edges]' (on the header line or the next one).
//  3. Check the declared counts against the content lines actually present before reserving
//     anything, so an absurd header cannot trigger a huge allocation or a long loop.
//  4. Vertices: 3 numbers each (extra values ignored); faces: a corner count then that many
//     indices in range (a colour after them ignored). Errors name the line.
#include "mesh/mesh_readers.h"
#include "mesh/text_tokens.h"

#include "errors.h"

#include <cstdint>
#include <limits>
#include <string_view>
#include <vector>

namespace hb::detail {

PolygonSoup read_off(const std::string& path, const std::string& text, MeshReadReport& report) {
  const auto invalid = [&](std::size_t line, const std::string& cause) {
    return InvalidInput(path + ":" + std::to_string(line) + ": " + cause);
  };
  if (text.find('\0') != std::string::npos)
    throw InvalidInput(path + ": not a text OFF file (contains NUL bytes; binary OFF is not supported)");

  LineReader lines(text);
  std::string_view line;
  if (!lines.next(line)) throw IoError(path + ": file has no content (only blanks or comments)");

  // Header keyword: [ST][C][N]OFF; "4OFF"/"nOFF" (other dimensions) and binary are refused.
  Tokens head(line);
  std::string_view tok;
  head.next(tok);
  std::vector<long long> counts;
  const std::string key(tok);
  const bool keyword = key.size() >= 3 && key.compare(key.size() - 3, 3, "OFF") == 0;
  if (keyword) {
    const std::string prefix = key.substr(0, key.size() - 3);
    if (prefix.find('4') != std::string::npos || prefix.find('n') != std::string::npos)
      throw invalid(lines.line_number(), "OFF variant '" + key + "' (not 3D) is not supported");
    for (char c : prefix)
      if (c != 'S' && c != 'T' && c != 'C' && c != 'N')
        throw invalid(lines.line_number(), "unrecognised OFF header '" + key + "'");
  } else {
    // Some writers omit the keyword; then the first line must be the counts.
    long long v;
    if (!parse_number(tok, v))
      throw invalid(lines.line_number(), "not an OFF file (header '" + key.substr(0, 40) + "')");
    counts.push_back(v);
  }
  while (head.next(tok)) {
    long long v;
    if (tok == "BINARY") throw invalid(lines.line_number(), "binary OFF is not supported");
    if (!parse_number(tok, v)) throw invalid(lines.line_number(), "bad count '" + std::string(tok) + "'");
    counts.push_back(v);
  }
  if (counts.empty()) {  // counts on their own line
    if (!lines.next(line)) throw IoError(path + ": truncated after the OFF header (no counts)");
    Tokens t(line);
    while (t.next(tok)) {
      long long v;
      if (!parse_number(tok, v)) throw invalid(lines.line_number(), "bad count '" + std::string(tok) + "'");
      counts.push_back(v);
    }
  }
  if (counts.size() < 2 || counts.size() > 3)
    throw invalid(lines.line_number(), "expected 'vertices faces [edges]' counts");
  if (counts[0] < 0 || counts[1] < 0) throw invalid(lines.line_number(), "negative vertex or face count");

  // Check the declared counts against the lines present before reserving anything, so an
  // absurd header cannot trigger a huge allocation or a long loop.
  const std::size_t available = count_content_lines(lines);
  const auto n_vertices = static_cast<std::size_t>(counts[0]);
  const auto n_faces = static_cast<std::size_t>(counts[1]);
  if (n_vertices > std::numeric_limits<std::uint32_t>::max())
    throw invalid(lines.line_number(), "vertex count " + std::to_string(n_vertices) + " is too large");
  if (n_vertices > available || n_faces > available - n_vertices)
    throw IoError(path + ": truncated: header declares " + std::to_string(n_vertices) + " vertices and " +
                  std::to_string(n_faces) + " faces but only " + std::to_string(available) +
                  " data lines follow");
  report.input_vertices = n_vertices;
  report.input_faces = n_faces;

  PolygonSoup soup;
  soup.positions.reserve(n_vertices);
  for (std::size_t v = 0; v < n_vertices; ++v) {
    lines.next(line);
    Tokens t(line);
    double c[3];
    for (double& x : c) {
      if (!t.next(tok) || !parse_number(tok, x))
        throw invalid(lines.line_number(), "vertex " + std::to_string(v) + ": expected 3 numeric coordinates");
    }
    // Extra values (normals, colours, texture coordinates) are ignored.
    soup.positions.emplace_back(float(c[0]), float(c[1]), float(c[2]));
  }

  soup.offsets.reserve(n_faces + 1);
  soup.indices.reserve(3 * n_faces);
  for (std::size_t f = 0; f < n_faces; ++f) {
    lines.next(line);
    Tokens t(line);
    long long k;
    if (!t.next(tok) || !parse_number(tok, k) || k < 0)
      throw invalid(lines.line_number(), "face " + std::to_string(f) + ": expected a corner count");
    if (static_cast<unsigned long long>(k) > line.size())  // each index needs >= 2 characters
      throw invalid(lines.line_number(), "face " + std::to_string(f) + ": corner count " + std::to_string(k) +
                                             " exceeds the line");
    for (long long i = 0; i < k; ++i) {
      long long idx;
      if (!t.next(tok) || !parse_number(tok, idx))
        throw invalid(lines.line_number(), "face " + std::to_string(f) + ": expected " + std::to_string(k) +
                                               " integer vertex indices");
      if (idx < 0 || idx >= static_cast<long long>(n_vertices))
        throw invalid(lines.line_number(), "face " + std::to_string(f) + ": vertex index " +
                                               std::to_string(idx) + " out of range [0, " +
                                               std::to_string(n_vertices) + ")");
      soup.indices.push_back(idx);
    }
    // Anything after the indices is a face colour: ignored.
    if (k < 3) {
      soup.indices.resize(soup.offsets.back());
      ++soup.short_faces;
      continue;
    }
    soup.offsets.push_back(soup.indices.size());
  }
  return soup;
}

} // namespace hb::detail
