// OBJ reader: a strict parser of our own (OpenMesh's skipped unparsable "v" lines silently,
// shifting every later index, and opened whatever file a "mtllib" line names).
//
//  1. Line by line ('#' comments, blank lines, a trailing '\' joins the next line, CRLF).
//  2. "v x y z [w | r g b]": three numbers within float range, or the line is refused.
//  3. "f c1 c2 c3 ...": each corner "i", "i/t", "i//n" or "i/t/n"; only i is used; a negative
//     i counts back from the last vertex read so far; 0 or a non-integer is refused. Indices
//     beyond the vertices are left to mesh_validation.cpp (which names the face).
//  4. Every other statement (vt, vn, g, o, s, usemtl, mtllib, l, p, curves) is ignored: no
//     other file is ever opened.
#include "mesh/mesh_readers.h"
#include "mesh/mesh_validation.h"
#include "mesh/text_tokens.h"

#include "errors.h"
#include "formats/quoted_text.h"

#include <cmath>
#include <limits>
#include <string_view>

namespace hb::detail {

PolygonSoup read_obj(const std::string& path, MeshReadReport& report) {
  const std::string text = read_whole_file(path);
  if (text.find('\0') != std::string::npos) throw InvalidInput(path + ": not a text OBJ file (contains NUL bytes)");
  PolygonSoup soup;
  LineReader lines(text);
  std::string_view line, tok;
  std::string joined;
  const auto fail = [&](const std::string& cause) {
    return InvalidInput(path + ":" + std::to_string(lines.line_number()) + ": " + cause);
  };
  while (lines.next(line)) {
    if (line.back() == '\\') {  // continuation lines
      joined.assign(line.substr(0, line.size() - 1));
      std::string_view more;
      while (!joined.empty() && lines.next(more)) {
        const bool again = more.back() == '\\';
        joined += ' ';
        joined.append(more.substr(0, more.size() - (again ? 1 : 0)));
        if (!again) break;
      }
      line = joined;
    }
    Tokens t(line);
    t.next(tok);
    if (tok == "v") {
      float c[3];
      for (float& x : c) {
        double v = 0.0;
        if (!t.next(tok) || !parse_number(tok, v))
          throw fail("vertex " + std::to_string(soup.positions.size()) + ": expected 3 numeric coordinates");
        if (!std::isfinite(v) || std::fabs(v) > double(std::numeric_limits<float>::max()))
          throw fail("vertex " + std::to_string(soup.positions.size()) + " has a non-finite (NaN or Inf) coordinate '" +
                     quoted_text(std::string(tok), 40) + "'");
        x = float(v);
      }
      soup.positions.emplace_back(c[0], c[1], c[2]);  // w or a colour after them: ignored
    } else if (tok == "f") {
      const std::size_t face = soup.face_count() + soup.short_faces;
      std::size_t corners = 0;
      while (t.next(tok)) {
        const std::string_view index = tok.substr(0, tok.find('/'));
        long long i = 0;
        if (!parse_number(index, i) || i == 0)
          throw fail("face " + std::to_string(face) + ": corner '" + quoted_text(std::string(tok), 40) +
                     "' is not a vertex index (1-based, or negative from the end)");
        const long long count = static_cast<long long>(soup.positions.size());
        soup.indices.push_back(i > 0 ? i - 1 : (i < -count ? -1 : count + i));  // out of range: refused later
        ++corners;
      }
      if (corners < 3) {
        soup.indices.resize(soup.offsets.back());
        ++soup.short_faces;
      } else {
        soup.offsets.push_back(soup.indices.size());
      }
    }
  }
  report.input_vertices = soup.positions.size();
  report.input_faces = soup.face_count() + soup.short_faces;
  return soup;
}

} // namespace hb::detail
