// hb_mutate_campaign: fresh mutations of the project's own model files through the load path
// the CLI uses (hb::vtk::load_model, which runs every foreign reader in a forked child under
// limits; the piece readers of `bake --pieces`), many per second in one process.
//
//  1. Seeds, per family: volumes (the generated CT phantom as .nii, .nii.gz, .mha, .nrrd; the
//     real DICOM series CT5N), cad (the
//     reference solid as STEP and as IGES, written here by OpenCASCADE), scenes (the elephant's
//     glTF + .bin, GLB, 3MF, Collada, FBX exports), pieces (a sphere's piece files .txt, .ply,
//     .vtp written here as `decompose` writes them). Volumes and scenes come from the generated
//     datasets (datasets/data/generated, see datasets/fetch.sh).
//  2. Each case damages its seed once, as scripts/mutate_models.py does (bit flips, an
//     interesting byte or integer, a truncation, a chunk cut out or repeated; for text formats
//     a number, line or token replaced, a line deleted or repeated, a reference changed), from
//     a generator seeded by (--seed, case index): a case is reproducible alone (--only N).
//  3. The case runs in a forked "outer" child that stands for the command a user runs: it calls
//     load_model (or the piece reader) with the campaign's reader limits and returns a summary
//     of the mesh. Outcomes:
//       crash      the outer child died by a signal: the command itself would have crashed
//       hang       the outer child passed twice the reader timeout plus 10 s
//       blowup     the outer child ran out of its memory (reader allowance + 2 GB)
//       empty      an error whose message does not start with the damaged file's path and a
//                  non-empty cause
//       contained  a clean error reporting that the isolated reader crashed, hung or ran out
//                  of memory (the command survives and says so; counted apart, as a pre-check
//                  could have said more)
//       rejected   any other clean error naming the file with a cause
//       unchanged  accepted, the same mesh as the undamaged seed (the damage missed)
//       changed    accepted, a different mesh, the same on a second load
//       unstable   accepted, but two loads of the same file differ (uninitialised reads)
//       suspect    changed, from a damage that changed the length of a file whose layout fixes
//                  its length (binary volumes, DICOM, GLB, glTF buffers, binary PLY, .vtp):
//                  a likely silent acceptance, to be read (--keep keeps the file)
//  4. --jobs workers (forked) share the cases; the summary gives per family the counts, the
//     processor seconds and the cost per run; --json writes every case.
// Usage: hb_mutate_campaign [--runs N] [--families volumes,cad,scenes,pieces] [--seed S]
//        [--jobs 2] [--timeout 3] [--memory-mb 2048] [--keep DIR] [--json FILE] [--only N]
//        (--keep keeps every case but a plain rejection or acceptance; with --only, the case
//        whatever its outcome)
//        [--bench REPS]  (valid files: load time with and without isolation)
//        [--write-seeds DIR]  (writes the generated seeds there and stops)
// Exit status 1 when any case is crash, hang, blowup, empty, unstable or suspect.
#include "errors.h"
#include "isolated_reader.h"
#include "model_loader.h"
#include "polydata_files.h"
#include "volume_phantom.h"
#include "decomposition/piece_file.h"
#include "mesh/generators.h"
#include "mesh/mesh_io.h"
#ifdef HB_HAVE_OCCT
#include "cad_reader.h"
#endif
#include <vtkPolyData.h>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <map>
#include <random>
#include <regex>
#include <sstream>
#include <string>
#include <fcntl.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>
#include <vector>
#include <zlib.h>
#include <thread>

namespace {

namespace fs = std::filesystem;

struct Seed {
  std::string family, path;
  bool text = false;        ///< text mutations apply (to the header, for .mha/.nrrd)
  bool dicom_dir = false;   ///< a series: one slice of a copy is damaged
  bool fixed_length = false;  ///< the layout fixes the file's length
  std::string companion;    ///< a file copied beside the damaged one (.gltf's .bin), or damaged instead
};

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw hb::IoError(path + ": cannot open");
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

void spit(const std::string& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary);
  out.write(bytes.data(), std::streamsize(bytes.size()));
  if (!out) throw hb::IoError(path + ": cannot write");
}

using Rng = std::mt19937_64;
std::size_t below(Rng& rng, std::size_t n) { return n == 0 ? 0 : std::size_t(rng() % n); }
bool chance(Rng& rng, double p) { return std::uniform_real_distribution<double>(0, 1)(rng) < p; }

// Binary damage; `kind` says which (a truncation, cut or repeat changes the length).
std::string mutate_binary(std::string b, Rng& rng, std::string& kind) {
  if (b.empty()) {
    kind = "empty";
    return b;
  }
  static const std::uint64_t interesting[] = {0, 1, 0xFF, 0x7F, 0x80, 0xFFFF, 0x7FFF, 0x8000, 0x7FFFFFFF, 0x80000000,
                                              0xFFFFFFFF, 0xFFFFFFF8, 65535, 1 << 20, 3};
  switch (below(rng, 6)) {
    case 0: {
      kind = "bitflip";
      const std::size_t n = 1 + below(rng, 8);
      for (std::size_t i = 0; i < n; ++i) b[below(rng, b.size())] ^= char(1 << below(rng, 8));
      break;
    }
    case 1: {
      kind = "byte";
      static const char bytes[] = {0, char(0xFF), 0x7F, char(0x80)};
      b[below(rng, b.size())] = bytes[below(rng, 4)];
      break;
    }
    case 2: {
      kind = "integer";
      const std::size_t width = chance(rng, 0.5) ? 2 : 4;
      const std::size_t at = below(rng, chance(rng, 0.7) ? std::min<std::size_t>(b.size(), 1024) : b.size());
      const std::uint64_t v = interesting[below(rng, std::size(interesting))];
      for (std::size_t k = 0; k < width && at + k < b.size(); ++k) b[at + k] = char((v >> (8 * k)) & 0xFF);
      break;
    }
    case 3:
      kind = "truncate";
      b.resize(below(rng, b.size()));
      break;
    case 4: {
      kind = "cut";
      const std::size_t at = below(rng, b.size());
      b.erase(at, 1 + below(rng, 256));
      break;
    }
    default: {
      kind = "repeat";
      const std::size_t at = below(rng, b.size());
      const std::string chunk = b.substr(at, 1 + below(rng, 256));
      std::string many;
      for (std::size_t i = 0, n = 1 + below(rng, 16); i < n; ++i) many += chunk;
      b.insert(at, many);
    }
  }
  return b;
}

std::vector<std::string> split_lines(const std::string& s) {
  std::vector<std::string> lines;
  std::size_t at = 0;
  for (;;) {
    const std::size_t nl = s.find('\n', at);
    if (nl == std::string::npos) {
      lines.push_back(s.substr(at));
      return lines;
    }
    lines.push_back(s.substr(at, nl - at));
    at = nl + 1;
  }
}

// Text damage within the first `header_end` bytes (all when npos).
std::string mutate_text(const std::string& data, Rng& rng, std::size_t header_end, std::string& kind) {
  const std::size_t end = std::min(header_end, data.size());
  std::vector<std::string> lines = split_lines(data.substr(0, end));
  if (lines.size() < 2) return mutate_binary(data, rng, kind);
  const std::size_t i = below(rng, lines.size());
  std::string& line = lines[i];
  static const char* numbers[] = {"0", "-1", "2147483648", "1e308", "nan", "-0", "99999999", "3", "65535", "4294967295", "1.5", ""};
  static const char* tokens[] = {"*", "#0", "#999999", "garbage", "\x01\x02", "LIST", "%d 1 10 0", "-1", ""};
  static const char* refs[] = {"#0", "#1", "#999999", "0", "1", "99999", "-1"};
  auto replace_match = [&](const std::regex& re, const char* const* choices, std::size_t count) {
    std::vector<std::pair<std::size_t, std::size_t>> spans;
    for (auto it = std::sregex_iterator(line.begin(), line.end(), re); it != std::sregex_iterator(); ++it)
      spans.emplace_back(std::size_t(it->position()), std::size_t(it->length()));
    if (spans.empty()) return;
    const auto [at, len] = spans[below(rng, spans.size())];
    line.replace(at, len, choices[below(rng, count)]);
  };
  switch (below(rng, 5)) {
    case 0: {
      kind = "number";
      static const std::regex number(R"(-?\d+(\.\d+)?(e[-+]?\d+)?)");
      replace_match(number, numbers, std::size(numbers));
      break;
    }
    case 1:
      kind = "line-deleted";
      lines.erase(lines.begin() + std::ptrdiff_t(i));
      break;
    case 2: {
      kind = "line-repeated";
      const std::string copy = line;
      lines.insert(lines.begin() + std::ptrdiff_t(i), copy);
      break;
    }
    case 3: {
      kind = "token";
      std::vector<std::string> toks;
      std::size_t at = 0;
      for (;;) {
        const std::size_t sp = line.find(' ', at);
        toks.push_back(line.substr(at, sp == std::string::npos ? std::string::npos : sp - at));
        if (sp == std::string::npos) break;
        at = sp + 1;
      }
      toks[below(rng, toks.size())] = tokens[below(rng, std::size(tokens))];
      line.clear();
      for (std::size_t k = 0; k < toks.size(); ++k) line += (k ? " " : "") + toks[k];
      break;
    }
    default: {
      kind = "reference";
      static const std::regex ref(R"(#\d+|"\d+"|\b\d+\b)");
      replace_match(ref, refs, std::size(refs));
    }
  }
  std::string out;
  for (std::size_t k = 0; k < lines.size(); ++k) out += (k ? "\n" : "") + lines[k];
  return out + data.substr(end);
}

std::size_t header_end_of(const std::string& name, const std::string& data) {
  if (name.size() > 4 && name.compare(name.size() - 4, 4, ".mha") == 0) {
    const std::size_t at = data.find("ElementDataFile = LOCAL\n");
    return at == std::string::npos ? std::string::npos : at + 24;
  }
  if (name.size() > 5 && name.compare(name.size() - 5, 5, ".nrrd") == 0) {
    const std::size_t at = data.find("\n\n");
    return at == std::string::npos ? std::string::npos : at + 2;
  }
  return std::string::npos;
}

std::string gunzip(const std::string& path) {
  gzFile f = gzopen(path.c_str(), "rb");
  if (!f) throw hb::IoError(path + ": cannot open");
  std::string out;
  char buf[1 << 16];
  int n;
  while ((n = gzread(f, buf, sizeof buf)) > 0) out.append(buf, std::size_t(n));
  gzclose(f);
  return out;
}

struct Options {
  std::size_t runs = 100;
  std::vector<std::string> families{"volumes", "cad", "scenes", "pieces"};
  std::uint64_t seed = 1;
  int jobs = 2;
  double timeout_s = 3.0;
  std::size_t memory_mb = 2048;
  std::string keep, json;
  long only = -1;
  int bench = 0;
  std::string write_seeds;
};

struct Campaign {
  Options opt;
  fs::path work;
  std::vector<Seed> seeds;
  std::string sphere;  // pieces: the mesh the piece files belong to
  std::size_t sphere_triangles = 0;
  std::map<std::string, std::string> baseline;  // seed path -> summary of its mesh
};

std::string data_dir() { return HB_DATASETS_DIR; }

void prepare_seeds(Campaign& c) {
  const fs::path g = fs::path(data_dir()) / "generated";
  const fs::path w = c.work / "seeds";
  fs::create_directories(w);
  auto want = [&](const std::string& f) { return std::find(c.opt.families.begin(), c.opt.families.end(), f) != c.opt.families.end(); };
  if (want("volumes")) {
    if (!fs::exists(g / "ct_phantom.nii.gz"))
      throw hb::IoError((g / "ct_phantom.nii.gz").string() + ": missing (run datasets/fetch.sh build/datasets/hb_generate_datasets)");
    spit((w / "ct_phantom.nii").string(), gunzip((g / "ct_phantom.nii.gz").string()));
    c.seeds.push_back({"volumes", (w / "ct_phantom.nii").string(), false, false, true, ""});
    c.seeds.push_back({"volumes", (g / "ct_phantom.nii.gz").string(), false, false, true, ""});
    c.seeds.push_back({"volumes", (g / "ct_phantom.mha").string(), true, false, true, ""});
    c.seeds.push_back({"volumes", (g / "ct_phantom.nrrd").string(), true, false, true, ""});
    const fs::path dicom = fs::path(data_dir()) / "volumes" / "dicom";
    for (const char* s : {"CT5N"})
      if (fs::exists(dicom / s)) c.seeds.push_back({"volumes", (dicom / s).string(), false, true, true, ""});
  }
#ifdef HB_HAVE_OCCT
  if (want("cad")) {
    hb::vtk::write_reference_solid_step((w / "reference_solid.step").string(), 10.0, 30.0);
    hb::vtk::write_reference_solid_iges((w / "reference_solid.igs").string(), 10.0, 30.0);
    c.seeds.push_back({"cad", (w / "reference_solid.step").string(), true, false, false, ""});
    c.seeds.push_back({"cad", (w / "reference_solid.igs").string(), true, false, false, ""});
  }
#endif
  if (want("scenes")) {
    c.seeds.push_back({"scenes", (g / "elephant.glb").string(), false, false, true, ""});
    c.seeds.push_back({"scenes", (g / "elephant.gltf").string(), true, false, false, (g / "elephant.bin").string()});
    c.seeds.push_back({"scenes", (g / "elephant.3mf").string(), false, false, true, ""});
    c.seeds.push_back({"scenes", (g / "elephant.dae").string(), true, false, false, ""});
    c.seeds.push_back({"scenes", (g / "elephant.fbx").string(), true, false, false, ""});  // ASCII FBX, as Assimp writes it
  }
  if (want("pieces")) {
    const hb::TriangleMesh sphere = hb::make_sphere(20.f, 3);
    c.sphere = (w / "sphere.off").string();
    hb::write_mesh(sphere, c.sphere);
    c.sphere_triangles = sphere.triangle_count();
    std::vector<std::uint32_t> ids(sphere.triangle_count());
    for (std::size_t t = 0; t < ids.size(); ++t) {
      const hb::Vec3 p = sphere.positions[sphere.triangles[t][0]];
      ids[t] = std::uint32_t((p.x() > 0) + 2 * (p.y() > 0));
    }
    hb::write_piece_file((w / "pieces.txt").string(), sphere, ids);
    hb::write_piece_file((w / "pieces.ply").string(), sphere, ids);
    hb::vtk::write_polydata_xml(hb::vtk::piece_polydata(sphere, ids), (w / "pieces.vtp").string());
    c.seeds.push_back({"pieces", (w / "pieces.txt").string(), true, false, false, ""});
    c.seeds.push_back({"pieces", (w / "pieces.ply").string(), slurp((w / "pieces.ply").string()).find("format ascii") != std::string::npos,
                       false, slurp((w / "pieces.ply").string()).find("format ascii") == std::string::npos, ""});
    c.seeds.push_back({"pieces", (w / "pieces.vtp").string(), true, false, true, ""});
  }
  for (const Seed& s : c.seeds)
    if (!fs::exists(s.path)) throw hb::IoError(s.path + ": seed missing (run datasets/fetch.sh build/datasets/hb_generate_datasets)");
}

// What a load gives: a summary of the mesh (counts, bounds, a hash of the coordinates).
std::string summary_of(const hb::TriangleMesh& mesh) {
  std::uint64_t h = 1469598103934665603ull;
  auto mix = [&](const void* p, std::size_t n) {
    const unsigned char* b = static_cast<const unsigned char*>(p);
    for (std::size_t i = 0; i < n; ++i) h = (h ^ b[i]) * 1099511628211ull;
  };
  mix(mesh.positions.data(), mesh.positions.size() * sizeof(hb::Vec3));
  mix(mesh.triangles.data(), mesh.triangles.size() * sizeof(hb::Triangle));
  std::ostringstream s;
  s << mesh.vertex_count() << " vertices, " << mesh.triangle_count() << " triangles, hash " << std::hex << h;
  return s.str();
}

std::string summary_of(const std::vector<std::uint32_t>& ids) {
  std::uint64_t h = 1469598103934665603ull;
  for (std::uint32_t v : ids) h = (h ^ v) * 1099511628211ull;
  std::ostringstream s;
  s << ids.size() << " piece ids, hash " << std::hex << h;
  return s.str();
}

// The command a user would run, in this process (the outer child).
std::string load_here(const Campaign& c, const std::string& family, const std::string& target) {
  if (family == "pieces") {
    if (target.size() > 4 && target.compare(target.size() - 4, 4, ".vtp") == 0)
      return summary_of(hb::vtk::read_piece_vtp(target, c.sphere_triangles));
    return summary_of(hb::read_piece_file(target, c.sphere_triangles));
  }
  hb::vtk::ModelOptions o;
  o.reader_timeout_s = c.opt.timeout_s;
  o.reader_memory_mb = c.opt.memory_mb;
  o.cad.chordal_deviation_mm = 0.1;  // --chordal-mm 0.1: the solids in about 2,000 triangles (the default, 0.02 mm, costs 5x)
  return summary_of(hb::vtk::load_model(target, o).mesh);
}

struct Result {
  std::size_t index = 0;
  std::string family, seed, mutation, outcome, message;
  double seconds = 0.0;
};

// Runs one load in an outer child; returns (ok, summary or message, outer failure?).
struct Load {
  bool ok = false;
  bool outer_failed = false;
  std::string text;
};

Load load_outer(const Campaign& c, const std::string& family, const std::string& target) {
  hb::vtk::ReaderLimits outer;
  outer.timeout_s = 2.0 * c.opt.timeout_s + 10.0;
  outer.memory_mb = c.opt.memory_mb + 2048;
  Load l;
  try {
    l.text = hb::vtk::run_isolated(target, "campaign's outer", outer, [&] { return load_here(c, family, target); });
    l.ok = true;
  } catch (const std::exception& e) {
    l.text = e.what();
    l.outer_failed = l.text.find("the campaign's outer reader failed") != std::string::npos;
  }
  return l;
}

bool length_changing(const std::string& kind) { return kind == "truncate" || kind == "cut" || kind == "repeat"; }

Result run_case(const Campaign& c, std::size_t index) {
  Result r;
  r.index = index;
  Rng rng(c.opt.seed * 0x9E3779B97F4A7C15ull + index);
  // The family and seed: cases cycle through the families, then a seed at random.
  const std::string& family = c.opt.families[index % c.opt.families.size()];
  std::vector<const Seed*> candidates;
  for (const Seed& s : c.seeds)
    if (s.family == family) candidates.push_back(&s);
  if (candidates.empty()) throw hb::InvalidInput("no seed for family " + family);
  const Seed& seed = *candidates[below(rng, candidates.size())];
  r.family = family;
  r.seed = fs::path(seed.path).filename().string();
  const fs::path cased = c.work / ("case" + std::to_string(index));
  fs::create_directories(cased);
  std::string target;
  bool fixed_length = seed.fixed_length;
  if (seed.dicom_dir) {
    const fs::path dir = cased / fs::path(seed.path).filename();
    fs::copy(seed.path, dir);
    std::vector<fs::path> slices;
    for (const auto& e : fs::directory_iterator(dir)) slices.push_back(e.path());
    std::sort(slices.begin(), slices.end());
    const fs::path victim = slices[below(rng, slices.size())];
    const std::string data = slurp(victim.string());
    std::string mutated;
    if (chance(rng, 0.5)) {
      mutated = mutate_binary(data, rng, r.mutation);
    } else {  // the header region, where the tags are
      const std::size_t head = std::min<std::size_t>(data.size(), 4096);
      mutated = mutate_binary(data.substr(0, head), rng, r.mutation) + data.substr(head);
    }
    spit(victim.string(), mutated);
    target = dir.string();
  } else {
    target = (cased / fs::path(seed.path).filename()).string();
    const std::string data = slurp(seed.path);
    std::string mutated;
    if (!seed.companion.empty()) {
      const std::string bin = (cased / fs::path(seed.companion).filename()).string();
      if (chance(rng, 0.3)) {  // damage the buffer instead of the JSON
        spit(bin, mutate_binary(slurp(seed.companion), rng, r.mutation));
        r.mutation = "bin-" + r.mutation;
        spit(target, data);
        fixed_length = true;
      } else {
        fs::copy_file(seed.companion, bin);
      }
    }
    if (r.mutation.empty()) {
      if (seed.text && chance(rng, 0.6)) mutated = mutate_text(data, rng, header_end_of(target, data), r.mutation);
      else mutated = mutate_binary(data, rng, r.mutation);
      spit(target, mutated);
    }
  }
  const auto start = std::chrono::steady_clock::now();
  const Load l = load_outer(c, family, target);
  if (l.ok) {
    const auto base = c.baseline.find(seed.path);
    if (base != c.baseline.end() && base->second == l.text) {
      r.outcome = "unchanged";
    } else {
      const Load again = load_outer(c, family, target);
      if (!again.ok || again.text != l.text) {
        r.outcome = "unstable";
        r.message = l.text + " / " + again.text;
      } else {
        r.outcome = fixed_length && length_changing(r.mutation) ? "suspect" : "changed";
        r.message = l.text;
      }
    }
  } else {
    const std::string& m = l.text;
    r.message = m;
    if (l.outer_failed) {
      if (m.find("it crashed") != std::string::npos || m.find("killed by signal") != std::string::npos) r.outcome = "crash";
      else if (m.find("still running") != std::string::npos || m.find("processor-time") != std::string::npos) r.outcome = "hang";
      else r.outcome = "blowup";
    } else {
      // The message must start with a path inside the case directory, then ": " and a cause.
      const std::string prefix = cased.string() + "/";
      std::size_t colon = std::string::npos;
      if (m.rfind(prefix, 0) == 0) colon = m.find(": ", prefix.size());
      const bool named = colon != std::string::npos;
      std::string cause = named ? m.substr(colon + 2) : "";
      cause.erase(0, cause.find_first_not_of(" \t\n"));
      if (!named || cause.empty()) r.outcome = "empty";
      else if (m.find(" reader failed on this file (") != std::string::npos) r.outcome = "contained";
      else r.outcome = "rejected";
    }
  }
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const bool bad = r.outcome != "rejected" && r.outcome != "unchanged" && r.outcome != "changed" && r.outcome != "contained";
  if (!c.opt.keep.empty() && (bad || r.outcome == "contained" || c.opt.only >= 0)) {
    const fs::path dest = fs::path(c.opt.keep) / (r.outcome + "-" + family + "-" + std::to_string(index));
    fs::create_directories(dest);
    fs::copy(cased, dest, fs::copy_options::recursive | fs::copy_options::overwrite_existing);
    spit((dest / "message.txt").string(), r.message + "\n");
  }
  std::error_code ec;
  fs::remove_all(cased, ec);
  return r;
}

std::string json_escape(const std::string& s) {
  std::string o;
  for (unsigned char ch : s) {
    if (ch == '"' || ch == '\\') o += '\\', o += char(ch);
    else if (ch == '\n') o += "\\n";
    else if (ch < 0x20 || ch >= 0x7F) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\u%04x", ch);
      o += buf;
    } else o += char(ch);
  }
  return o;
}

double cpu_seconds_of_children_and_self() {
  rusage self{}, kids{};
  getrusage(RUSAGE_SELF, &self);
  getrusage(RUSAGE_CHILDREN, &kids);
  auto s = [](const timeval& t) { return double(t.tv_sec) + 1e-6 * double(t.tv_usec); };
  return s(self.ru_utime) + s(self.ru_stime) + s(kids.ru_utime) + s(kids.ru_stime);
}

// A worker: the cases index % jobs == w, one JSON line each into `out`.
void worker(const Campaign& c, int w, const std::string& out) {
  // Readers' children orphaned by an outer child that exited first come here to be reaped, so
  // that their processor time is counted.
  ::prctl(PR_SET_CHILD_SUBREAPER, 1);
  // The libraries' console messages (VTK's, Assimp's) would bury the summary.
  if (const int null = ::open("/dev/null", O_WRONLY); null >= 0) ::dup2(null, STDERR_FILENO);
  auto reap = [](int flags) {
    int st = 0;
    while (::waitpid(-1, &st, flags) > 0) {
    }
  };
  std::ofstream o(out);
  const std::size_t total = c.opt.runs * c.opt.families.size();
  for (std::size_t i = std::size_t(w); i < total; i += std::size_t(c.opt.jobs)) {
    if (c.opt.only >= 0 && i != std::size_t(c.opt.only)) continue;
    Result r;
    try {
      r = run_case(c, i);
    } catch (const std::exception& e) {
      r.index = i;
      r.outcome = "driver-error";
      r.message = e.what();
    }
    o << "{\"index\":" << r.index << ",\"family\":\"" << r.family << "\",\"seed\":\"" << json_escape(r.seed) << "\",\"mutation\":\""
      << r.mutation << "\",\"outcome\":\"" << r.outcome << "\",\"seconds\":" << r.seconds << ",\"message\":\""
      << json_escape(r.message.substr(0, 400)) << "\"}\n"
      << std::flush;
    reap(WNOHANG);
  }
  reap(0);
}

std::string field(const std::string& line, const std::string& name) {
  const std::string key = "\"" + name + "\":";
  const std::size_t at = line.find(key);
  if (at == std::string::npos) return "";
  std::size_t v = at + key.size();
  if (line[v] == '"') {
    std::string out;
    for (std::size_t k = v + 1; k < line.size() && line[k] != '"'; ++k) {
      if (line[k] == '\\' && k + 1 < line.size()) ++k;
      out += line[k];
    }
    return out;
  }
  const std::size_t end = line.find_first_of(",}", v);
  return line.substr(v, end - v);
}

// Valid files: load_model with and without isolation, alternating, `reps` times each.
int bench(const Campaign& c) {
  struct File {
    std::string name, path;
    bool vtk_readers;
  };
  const fs::path d = data_dir();
  std::vector<File> files = {{"armadillo.off (core reader)", (d / "meshes" / "armadillo.off").string(), false},
                             {"armadillo.off as .ply through VTK", "", true},
                             {"CT phantom .nii.gz", (d / "generated" / "ct_phantom.nii.gz").string(), false},
                             {"CT phantom .mha", (d / "generated" / "ct_phantom.mha").string(), false},
                             {"femur CT .nii.gz", (d / "generated" / "femur_ct.nii.gz").string(), false},
                             {"DICOM CT5N", (d / "volumes" / "dicom" / "CT5N").string(), false},
                             {"STEP reference solid", (d / "generated" / "reference_solid.step").string(), false},
                             {"elephant .gltf", (d / "generated" / "elephant.gltf").string(), false},
                             {"elephant .glb", (d / "generated" / "elephant.glb").string(), false},
                             {"pieces .vtp (sphere)", "", false}};
  {
    const hb::TriangleMesh armadillo = hb::read_mesh(files[0].path);
    files[1].path = (c.work / "armadillo.ply").string();
    hb::write_mesh(armadillo, files[1].path);
    std::vector<std::uint32_t> ids(armadillo.triangle_count());
    for (std::size_t t = 0; t < ids.size(); ++t) ids[t] = std::uint32_t(t % 7);
    files.back().path = (c.work / "armadillo_pieces.vtp").string();
    files.back().name = "armadillo pieces .vtp";
    hb::vtk::write_polydata_xml(hb::vtk::piece_polydata(armadillo, ids), files.back().path);
  }
  std::printf("%-34s %10s %10s %7s %10s %10s %7s  (medians; direct and isolated alternate)\n", "file", "direct ms", "isolated", "ratio",
              "cpu ms", "isolated", "ratio");
  {
    // The isolation alone: a reader that returns at once, and one that returns 10 MB.
    hb::vtk::ReaderLimits limits;
    for (const std::size_t bytes : {std::size_t(0), std::size_t(10) << 20}) {
      std::vector<double> ms;
      for (int rep = 0; rep < 2 * c.opt.bench + 1; ++rep) {
        const auto t0 = std::chrono::steady_clock::now();
        hb::vtk::run_isolated("x", "empty", limits, [&] { return std::string(bytes, 'x'); });
        ms.push_back(1e3 * std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
      }
      std::sort(ms.begin(), ms.end());
      std::printf("run_isolated returning %zu MB: %.1f ms (median)\n", bytes >> 20, ms[ms.size() / 2]);
    }
  }
  for (const File& f : files) {
    if (!fs::exists(f.path)) continue;
    hb::vtk::ModelOptions o;
    o.use_vtk_readers = f.vtk_readers;
    std::vector<double> direct, isolated, direct_cpu, isolated_cpu;
    for (int rep = 0; rep < c.opt.bench + 1; ++rep) {
      for (int iso = 0; iso < 2; ++iso) {
        if (iso) ::unsetenv("HB_READER_ISOLATION");
        else ::setenv("HB_READER_ISOLATION", "0", 1);
        const double cpu0 = cpu_seconds_of_children_and_self();
        const auto t0 = std::chrono::steady_clock::now();
        if (f.path.size() > 4 && f.path.compare(f.path.size() - 4, 4, ".vtp") == 0 && f.name.find("pieces") != std::string::npos)
          hb::vtk::read_piece_vtp(f.path, 0);
        else
          hb::vtk::load_model(f.path, o);
        const double ms = 1e3 * std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        // The child's processor time counts once it is reaped (in the background, after its
        // result): let that happen.
        std::this_thread::sleep_for(std::chrono::milliseconds(60));
        const double cpu_ms = 1e3 * (cpu_seconds_of_children_and_self() - cpu0);
        if (rep > 0) {  // the first round warms the caches
          (iso ? isolated : direct).push_back(ms);
          (iso ? isolated_cpu : direct_cpu).push_back(cpu_ms);
        }
      }
    }
    ::unsetenv("HB_READER_ISOLATION");
    auto median = [](std::vector<double> v) {
      std::sort(v.begin(), v.end());
      return v[v.size() / 2];
    };
    std::printf("%-34s %10.1f %10.1f %7.2f %10.1f %10.1f %7.2f\n", f.name.c_str(), median(direct), median(isolated),
                median(isolated) / median(direct), median(direct_cpu), median(isolated_cpu), median(isolated_cpu) / median(direct_cpu));
  }
  return 0;
}

[[noreturn]] void usage(const std::string& why) {
  std::cerr << "hb_mutate_campaign: " << why
            << "\nusage: hb_mutate_campaign [--runs N] [--families volumes,cad,scenes,pieces] [--seed S] [--jobs J] "
               "[--timeout S] [--memory-mb M] [--keep DIR] [--json FILE] [--only N] [--bench REPS] [--write-seeds DIR]\n";
  std::exit(2);
}

} // namespace

int main(int argc, char** argv) {
  Campaign c;
  Options& o = c.opt;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) usage(a + " needs a value");
      return argv[++i];
    };
    try {
      if (a == "--runs") o.runs = std::stoul(value());
      else if (a == "--families") {
        o.families.clear();
        std::stringstream s(value());
        for (std::string f; std::getline(s, f, ',');) {
          if (f != "volumes" && f != "cad" && f != "scenes" && f != "pieces") usage("unknown family " + f);
          o.families.push_back(f);
        }
      } else if (a == "--seed") o.seed = std::stoull(value());
      else if (a == "--jobs") o.jobs = std::max(1, std::stoi(value()));
      else if (a == "--timeout") o.timeout_s = std::stod(value());
      else if (a == "--memory-mb") o.memory_mb = std::stoul(value());
      else if (a == "--keep") o.keep = value();
      else if (a == "--json") o.json = value();
      else if (a == "--only") o.only = std::stol(value());
      else if (a == "--bench") o.bench = std::stoi(value());
      else if (a == "--write-seeds") o.write_seeds = value();
      else usage("unknown option " + a);
    } catch (const std::logic_error&) {
      usage("bad value for " + a);
    }
  }
  if (o.families.empty() || !(o.timeout_s > 0) || o.memory_mb < 64) usage("bad families, timeout or memory");
  // The readers that take their limits from the environment only (read_piece_vtp) get the
  // campaign's too.
  ::setenv("HB_READER_TIMEOUT_S", std::to_string(o.timeout_s).c_str(), 1);
  ::setenv("HB_READER_MEMORY_MB", std::to_string(o.memory_mb).c_str(), 1);
  c.work = fs::temp_directory_path() / ("hb_campaign_" + std::to_string(::getpid()));
  fs::create_directories(c.work);
  struct Cleanup {
    fs::path p;
    ~Cleanup() {
      std::error_code ec;
      fs::remove_all(p, ec);
    }
  } cleanup{c.work};
  try {
    if (o.bench > 0) return bench(c);
    prepare_seeds(c);
    if (!o.write_seeds.empty()) {
      fs::create_directories(o.write_seeds);
      for (const auto& e : fs::directory_iterator(c.work / "seeds")) fs::copy(e.path(), fs::path(o.write_seeds) / e.path().filename(),
                                                                           fs::copy_options::overwrite_existing);
      std::cout << "hb_mutate_campaign: the generated seeds are in " << o.write_seeds << "\n";
      return 0;
    }
    for (const Seed& s : c.seeds) {
      std::string target = s.path;
      const Load l = load_outer(c, s.family, target);
      if (!l.ok) throw hb::InvalidInput("seed " + s.path + " does not load: " + l.text);
      c.baseline[s.path] = l.text;
    }
  } catch (const std::exception& e) {
    std::cerr << "hb_mutate_campaign: " << e.what() << "\n";
    return 2;
  }
  if (!o.keep.empty()) fs::create_directories(o.keep);
  const auto start = std::chrono::steady_clock::now();
  const double cpu_before = cpu_seconds_of_children_and_self();
  std::vector<pid_t> pids;
  std::vector<std::string> outs;
  std::cout.flush();
  for (int w = 0; w < o.jobs; ++w) {
    outs.push_back((c.work / ("worker" + std::to_string(w) + ".jsonl")).string());
    const pid_t pid = ::fork();
    if (pid == 0) {
      worker(c, w, outs.back());
      std::_Exit(0);
    }
    pids.push_back(pid);
  }
  for (pid_t p : pids) {
    int st = 0;
    while (::waitpid(p, &st, 0) < 0 && errno == EINTR) {
    }
    if (!WIFEXITED(st) || WEXITSTATUS(st) != 0) std::cerr << "hb_mutate_campaign: a worker died (status " << st << ")\n";
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const double cpu = cpu_seconds_of_children_and_self() - cpu_before;
  // Merge.
  const std::vector<std::string> outcomes = {"crash", "hang", "blowup", "empty", "unstable", "suspect", "contained", "rejected",
                                             "changed", "unchanged", "driver-error"};
  std::map<std::string, std::map<std::string, std::size_t>> counts;
  std::map<std::string, double> seconds;
  std::map<std::string, std::size_t> runs;
  std::vector<std::string> bad;
  std::ofstream json;
  if (!o.json.empty()) json.open(o.json);
  for (const std::string& f : outs) {
    std::ifstream in(f);
    for (std::string line; std::getline(in, line);) {
      if (json.is_open()) json << line << "\n";
      const std::string fam = field(line, "family"), out = field(line, "outcome");
      ++counts[fam][out];
      ++runs[fam];
      seconds[fam] += std::stod(field(line, "seconds"));
      if (out == "crash" || out == "hang" || out == "blowup" || out == "empty" || out == "unstable" || out == "suspect" ||
          out == "driver-error")
        bad.push_back(out + " #" + field(line, "index") + " " + field(line, "seed") + " (" + field(line, "mutation") +
                      "): " + field(line, "message"));
    }
  }
  std::printf("hb_mutate_campaign: seed %llu, %zu runs a family, %d jobs, reader limits %.1f s / %zu MB\n",
              static_cast<unsigned long long>(o.seed), o.runs, o.jobs, o.timeout_s, o.memory_mb);
  std::printf("%-8s %6s", "family", "runs");
  for (const std::string& k : outcomes) std::printf(" %9s", k.c_str());
  std::printf(" %9s %8s\n", "seconds", "ms/run");
  for (const std::string& fam : o.families) {
    std::printf("%-8s %6zu", fam.c_str(), runs[fam]);
    for (const std::string& k : outcomes) std::printf(" %9zu", counts[fam][k]);
    std::printf(" %9.0f %8.1f\n", seconds[fam], runs[fam] ? 1e3 * seconds[fam] / double(runs[fam]) : 0.0);
  }
  std::printf("wall %.0f s, processor %.0f s (workers and their children), %.1f ms of processor a run\n", wall, cpu,
              1e3 * cpu / double(std::max<std::size_t>(1, [&] {
                std::size_t n = 0;
                for (auto& [f, k] : runs) n += k;
                return n;
              }())));
  for (std::size_t i = 0; i < bad.size() && i < 60; ++i) std::printf("  %s\n", bad[i].substr(0, 400).c_str());
  return bad.empty() ? 0 : 1;
}
