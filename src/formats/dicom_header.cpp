// A DICOM file walked element by element (see dicom_header.h): group 2 in explicit VR little
// endian, the data set in its transfer syntax; sequences (defined or undefined length) are
// skipped item by item, to a bounded depth. Only the elements HapticBox needs are kept.
#include "formats/dicom_header.h"
#include "errors.h"
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <sstream>
#include <vector>

namespace hb {

namespace {

const char* const kImplicitLE = "1.2.840.10008.1.2";
const char* const kExplicitLE = "1.2.840.10008.1.2.1";
const char* const kExplicitBE = "1.2.840.10008.1.2.2";

std::string hex4(unsigned v) {
  char b[8];
  std::snprintf(b, sizeof b, "%04X", v & 0xFFFFu);
  return b;
}

std::string tag_name(unsigned group, unsigned element) { return "(" + hex4(group) + "," + hex4(element) + ")"; }

std::string trimmed(const std::string& s) {
  std::size_t a = 0, b = s.size();
  while (a < b && (s[a] == ' ' || s[a] == '\0')) ++a;
  while (b > a && (s[b - 1] == ' ' || s[b - 1] == '\0')) --b;
  return s.substr(a, b - a);
}

// "a\b\c" as numbers; empty when one is not a finite number.
std::vector<double> numbers(const std::string& s) {
  std::vector<double> out;
  std::stringstream in(s);
  for (std::string part; std::getline(in, part, '\\');) {
    part = trimmed(part);
    char* end = nullptr;
    const double d = std::strtod(part.c_str(), &end);
    if (part.empty() || *end || !std::isfinite(d)) return {};
    out.push_back(d);
  }
  return out;
}

bool long_vr(const char* vr) {
  for (const char* v : {"OB", "OW", "OF", "SQ", "UT", "UN", "OD", "OL", "OV", "UC", "UR", "SV", "UV"})
    if (vr[0] == v[0] && vr[1] == v[1]) return true;
  return false;
}

class Walker {
public:
  Walker(const std::string& name, const std::string& bytes, DicomHeader& out) : name_(name), b_(bytes), out_(out) {}

  void run() {
    std::size_t at = 0;
    if (looks_like_dicom(b_)) at = 132;
    else if (!(b_.size() >= 8 && (u16(0, false) == 0x0002 || u16(0, false) == 0x0008)))
      throw InvalidInput(name_ + ": not a DICOM file (no \"DICM\" at byte 128 and no DICOM element at the start)");
    // Group 2: explicit VR little endian.
    bool saw_ts = false;
    while (at + 4 <= b_.size() && u16(at, false) == 0x0002) at = element(at, true, false, 0, &saw_ts);
    std::string ts = out_.transfer_syntax;
    if (saw_ts && ts.empty()) throw InvalidInput(name_ + ": the TransferSyntaxUID (0002,0010) is empty");
    if (!saw_ts) ts = kImplicitLE;  // no meta header: the DICOM default
    bool explicit_vr = true, big = false;
    if (ts == kImplicitLE) explicit_vr = false;
    else if (ts == kExplicitLE) explicit_vr = true;
    else if (ts == kExplicitBE) big = true;
    else
      throw InvalidInput(name_ + ": transfer syntax " + ts +
                         " (compressed or unknown) is not supported: only uncompressed (implicit or explicit VR) DICOM");
    while (at < b_.size()) {
      if (b_.size() - at < 8) throw InvalidInput(name_ + ": the file ends inside an element header at byte " + std::to_string(at));
      at = element(at, explicit_vr, big, 0, nullptr);
    }
  }

private:
  unsigned u16(std::size_t at, bool big) const {
    const auto* p = reinterpret_cast<const unsigned char*>(b_.data() + at);
    return big ? (unsigned(p[0]) << 8 | p[1]) : (unsigned(p[1]) << 8 | p[0]);
  }
  std::uint32_t u32(std::size_t at, bool big) const {
    const auto* p = reinterpret_cast<const unsigned char*>(b_.data() + at);
    return big ? (std::uint32_t(p[0]) << 24 | std::uint32_t(p[1]) << 16 | std::uint32_t(p[2]) << 8 | p[3])
               : (std::uint32_t(p[3]) << 24 | std::uint32_t(p[2]) << 16 | std::uint32_t(p[1]) << 8 | p[0]);
  }
  void need(std::size_t at, std::uint64_t n, const std::string& what) const {
    if (at > b_.size() || n > b_.size() - at)
      throw InvalidInput(name_ + ": " + what + " runs past the end of the file (" + std::to_string(n) + " bytes at byte " +
                         std::to_string(at) + " of " + std::to_string(b_.size()) + ")");
  }

  // One element at `at`; returns the offset after it.
  std::size_t element(std::size_t at, bool explicit_vr, bool big, int depth, bool* saw_ts) {
    need(at, 8, "an element header");
    const unsigned group = u16(at, big), elem = u16(at + 2, big);
    std::uint32_t length;
    std::size_t value_at;
    char vr[3] = {0, 0, 0};
    if (explicit_vr && group != 0xFFFE) {
      vr[0] = b_[at + 4];
      vr[1] = b_[at + 5];
      if (vr[0] < 'A' || vr[0] > 'Z' || vr[1] < 'A' || vr[1] > 'Z')
        throw InvalidInput(name_ + ": element " + tag_name(group, elem) + " at byte " + std::to_string(at) + " has no valid VR");
      if (long_vr(vr)) {
        need(at, 12, "element " + tag_name(group, elem));
        length = u32(at + 8, big);
        value_at = at + 12;
      } else {
        length = u16(at + 6, big);
        value_at = at + 8;
      }
    } else {
      length = u32(at + 4, big);
      value_at = at + 8;
    }
    if (length == 0xFFFFFFFFu) {
      if (group == 0x7FE0 && elem == 0x0010)
        throw InvalidInput(name_ + ": the pixel data is encapsulated (compressed): not supported");
      return sequence(value_at, explicit_vr, big, depth + 1, tag_name(group, elem));
    }
    need(value_at, length, "element " + tag_name(group, elem));
    const std::string value = b_.substr(value_at, std::min<std::uint32_t>(length, 1024));
    if (depth == 0) keep(group, elem, value, length, big, saw_ts);
    return value_at + length;
  }

  // Items of an undefined-length sequence, up to its delimiter.
  std::size_t sequence(std::size_t at, bool explicit_vr, bool big, int depth, const std::string& tag) {
    if (depth > 16) throw InvalidInput(name_ + ": sequences nested deeper than 16 levels at " + tag);
    for (;;) {
      need(at, 8, "an item of sequence " + tag);
      const unsigned group = u16(at, big), elem = u16(at + 2, big);
      const std::uint32_t length = u32(at + 4, big);
      at += 8;
      if (group != 0xFFFE) throw InvalidInput(name_ + ": sequence " + tag + " holds a non-item element " + tag_name(group, elem));
      if (elem == 0xE0DD) return at;  // sequence delimiter
      if (elem != 0xE000) throw InvalidInput(name_ + ": sequence " + tag + " holds an unknown delimiter " + tag_name(group, elem));
      if (length != 0xFFFFFFFFu) {
        need(at, length, "an item of sequence " + tag);
        at += length;
        continue;
      }
      // An undefined-length item: elements up to the item delimiter.
      for (;;) {
        need(at, 8, "an item of sequence " + tag);
        if (u16(at, big) == 0xFFFE && u16(at + 2, big) == 0xE00D) {
          at += 8;
          break;
        }
        at = element(at, explicit_vr, big, depth, nullptr);
      }
    }
  }

  void keep(unsigned group, unsigned elem, const std::string& value, std::uint32_t length, bool big, bool* saw_ts) {
    const std::uint32_t tag = std::uint32_t(group) << 16 | elem;
    auto us = [&](const char* what) -> unsigned {
      if (length != 2) throw InvalidInput(name_ + ": " + std::string(what) + " " + tag_name(group, elem) + " is " +
                                          std::to_string(length) + " bytes, not 2");
      const auto* p = reinterpret_cast<const unsigned char*>(value.data());
      return big ? (unsigned(p[0]) << 8 | p[1]) : (unsigned(p[1]) << 8 | p[0]);
    };
    auto text = [&](const char* what) {
      const std::string t = trimmed(value);
      if (t.empty()) throw InvalidInput(name_ + ": " + std::string(what) + " " + tag_name(group, elem) + " is empty");
      return t;
    };
    switch (tag) {
      case 0x00020010: out_.transfer_syntax = trimmed(value); if (saw_ts) *saw_ts = true; break;
      case 0x0020000E: out_.series_uid = trimmed(value); break;
      case 0x00080060: out_.modality = trimmed(value); break;
      case 0x00280004: out_.photometric = text("PhotometricInterpretation"); break;
      case 0x00280010: out_.rows = us("Rows"); break;
      case 0x00280011: out_.columns = us("Columns"); break;
      case 0x00280100: out_.bits_allocated = us("BitsAllocated"); break;
      case 0x00280002: out_.samples_per_pixel = us("SamplesPerPixel"); break;
      case 0x00280008: {
        const std::vector<double> n = numbers(text("NumberOfFrames"));
        if (n.size() != 1 || n[0] < 1 || n[0] > 65535 || n[0] != std::floor(n[0]))
          throw InvalidInput(name_ + ": NumberOfFrames (0028,0008) is '" + trimmed(value) + "'");
        out_.frames = unsigned(n[0]);
        break;
      }
      case 0x00281053: {
        const std::vector<double> n = numbers(text("RescaleSlope"));
        if (n.size() != 1 || n[0] == 0) throw InvalidInput(name_ + ": RescaleSlope (0028,1053) is '" + trimmed(value) + "', not a non-zero number");
        out_.has_rescale_slope = true;
        break;
      }
      case 0x00281052: {
        if (numbers(text("RescaleIntercept")).size() != 1)
          throw InvalidInput(name_ + ": RescaleIntercept (0028,1052) is '" + trimmed(value) + "', not a number");
        break;
      }
      case 0x00200032: {
        if (numbers(text("ImagePositionPatient")).size() != 3)
          throw InvalidInput(name_ + ": ImagePositionPatient (0020,0032) is '" + trimmed(value) + "', not 3 numbers");
        out_.has_position = true;
        break;
      }
      case 0x00200037: {
        const std::vector<double> n = numbers(text("ImageOrientationPatient"));
        if (n.size() != 6) throw InvalidInput(name_ + ": ImageOrientationPatient (0020,0037) is '" + trimmed(value) + "', not 6 numbers");
        const double r = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]), c = std::sqrt(n[3] * n[3] + n[4] * n[4] + n[5] * n[5]);
        const double dot = n[0] * n[3] + n[1] * n[4] + n[2] * n[5];
        if (std::abs(r - 1) > 0.01 || std::abs(c - 1) > 0.01 || std::abs(dot) > 0.01)
          throw InvalidInput(name_ + ": ImageOrientationPatient (0020,0037) '" + trimmed(value) +
                             "' is not two perpendicular unit vectors");
        out_.has_orientation = true;
        break;
      }
      case 0x00280030: {
        const std::vector<double> n = numbers(text("PixelSpacing"));
        if (n.size() != 2 || !(n[0] > 0) || !(n[1] > 0) || n[0] > 1e4 || n[1] > 1e4)
          throw InvalidInput(name_ + ": PixelSpacing (0028,0030) is '" + trimmed(value) + "', not two sizes > 0 in mm");
        out_.has_spacing = true;
        break;
      }
      case 0x7FE00010: out_.has_pixel_data = true; out_.pixel_bytes = length; break;
      default: break;
    }
  }

  const std::string& name_;
  const std::string& b_;
  DicomHeader& out_;
};

} // namespace

bool looks_like_dicom(const std::string& bytes) { return bytes.size() >= 132 && bytes.compare(128, 4, "DICM") == 0; }

DicomHeader check_dicom_header(const std::string& name, const std::string& bytes) {
  DicomHeader h;
  Walker(name, bytes, h).run();
  if (!h.has_pixel_data) throw InvalidInput(name + ": no PixelData (7FE0,0010): not an image");
  if (h.rows == 0 || h.columns == 0)
    throw InvalidInput(name + ": Rows (0028,0010) and Columns (0028,0011) must both be present and > 0 (they are " +
                       std::to_string(h.rows) + " and " + std::to_string(h.columns) + ")");
  if (h.bits_allocated != 8 && h.bits_allocated != 16 && h.bits_allocated != 32)
    throw InvalidInput(name + ": BitsAllocated (0028,0100) is " + std::to_string(h.bits_allocated) + ", not 8, 16 or 32");
  if (h.samples_per_pixel != 1)
    throw InvalidInput(name + ": " + std::to_string(h.samples_per_pixel) + " samples per pixel (colour): not a slice of a volume");
  if (h.photometric.empty()) throw InvalidInput(name + ": no PhotometricInterpretation (0028,0004)");
  if (!h.has_position) throw InvalidInput(name + ": no ImagePositionPatient (0020,0032): not a slice of a volume");
  if (!h.has_orientation) throw InvalidInput(name + ": no ImageOrientationPatient (0020,0037): not a slice of a volume");
  if (!h.has_spacing) throw InvalidInput(name + ": no PixelSpacing (0028,0030): the slice's size is unknown");
  if (h.frames != 1) throw InvalidInput(name + ": " + std::to_string(h.frames) + " frames in one file: only one slice a file is supported");
  const std::uint64_t needed = std::uint64_t(h.rows) * h.columns * (h.bits_allocated / 8);
  if (h.pixel_bytes != needed && h.pixel_bytes != needed + 1)  // + 1: odd lengths are padded
    throw InvalidInput(name + ": " + std::to_string(h.rows) + " rows x " + std::to_string(h.columns) + " columns x " +
                       std::to_string(h.bits_allocated) + " bits make " + std::to_string(needed) + " bytes, the pixel data holds " +
                       std::to_string(h.pixel_bytes) + ": the header does not describe the image");
  return h;
}

} // namespace hb
