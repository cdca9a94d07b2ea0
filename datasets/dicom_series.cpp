// write_dicom_series: the smallest complete CT series VTK's DICOM reader and scanners' viewers
// take. Every element is written with its explicit VR; strings are padded to even lengths.
#include "dicom_series.h"
#include "errors.h"
#include <vtkImageData.h>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

namespace hb::datasets {

namespace {

class Writer {
public:
  void element(std::uint16_t group, std::uint16_t tag, const char vr[2], std::string value, char pad = ' ') {
    if (value.size() % 2) value += (std::string(vr, 2) == "UI" ? '\0' : pad);
    header(group, tag, vr, value.size());
    bytes_ += value;
  }
  void us(std::uint16_t group, std::uint16_t tag, std::uint16_t v) {
    header(group, tag, "US", 2);
    u16(v);
  }
  void ul(std::uint16_t group, std::uint16_t tag, std::uint32_t v) {
    header(group, tag, "UL", 4);
    u32(v);
  }
  void pixels(const std::int16_t* data, std::size_t count) {
    header(0x7fe0, 0x0010, "OW", count * 2);
    bytes_.append(reinterpret_cast<const char*>(data), count * 2);  // little endian on x86
  }
  void ob(std::uint16_t group, std::uint16_t tag, const std::string& v) {
    header(group, tag, "OB", v.size());
    bytes_ += v;
  }
  const std::string& bytes() const { return bytes_; }

private:
  void u16(std::uint16_t v) { bytes_ += char(v & 0xff), bytes_ += char(v >> 8); }
  void u32(std::uint32_t v) { u16(std::uint16_t(v & 0xffff)), u16(std::uint16_t(v >> 16)); }
  void header(std::uint16_t group, std::uint16_t tag, const char vr[2], std::size_t length) {
    u16(group);
    u16(tag);
    bytes_.append(vr, 2);
    const std::string v(vr, 2);
    if (v == "OB" || v == "OW" || v == "SQ" || v == "UN" || v == "UT") {
      u16(0);
      u32(std::uint32_t(length));
    } else {
      u16(std::uint16_t(length));
    }
  }
  std::string bytes_;
};

std::string ds(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.6g", v);
  return text;
}

} // namespace

void write_dicom_series(vtkImageData* image, const Eigen::Matrix4d& index_to_mm, const std::string& folder,
                        const std::string& patient_name, const std::string& description) {
  namespace fs = std::filesystem;
  std::error_code ec;
  fs::create_directories(folder, ec);
  if (ec) throw IoError(folder + ": cannot create folder (" + ec.message() + ")");
  const int* d = image->GetDimensions();
  const auto* voxels = static_cast<const std::int16_t*>(image->GetScalarPointer());
  const Eigen::Vector3d di = index_to_mm.block<3, 1>(0, 0), dj = index_to_mm.block<3, 1>(0, 1), dk = index_to_mm.block<3, 1>(0, 2);
  const Eigen::Vector3d row = di.normalized(), column = dj.normalized();
  const std::string root = "1.2.826.0.1.3680043.9.7433.20261206";  // a fixed root: the data is made, not scanned
  const std::string study = root + ".1", series = root + ".2", frame = root + ".3";
  const std::string ct = "1.2.840.10008.5.1.4.1.1.2";
  std::vector<std::int16_t> slice(std::size_t(d[0]) * std::size_t(d[1]));
  for (int k = 0; k < d[2]; ++k) {
    const std::string instance = root + ".4." + std::to_string(k + 1);
    Writer meta;
    meta.ob(0x0002, 0x0001, std::string("\0\1", 2));
    meta.element(0x0002, 0x0002, "UI", ct);
    meta.element(0x0002, 0x0003, "UI", instance);
    meta.element(0x0002, 0x0010, "UI", "1.2.840.10008.1.2.1");
    meta.element(0x0002, 0x0012, "UI", root + ".9");
    Writer w;
    w.element(0x0008, 0x0008, "CS", "DERIVED\\SECONDARY\\AXIAL");
    w.element(0x0008, 0x0016, "UI", ct);
    w.element(0x0008, 0x0018, "UI", instance);
    w.element(0x0008, 0x0060, "CS", "CT");
    w.element(0x0008, 0x0070, "LO", "HapticBox hb_generate_models (synthesized)");
    w.element(0x0008, 0x103e, "LO", description);
    w.element(0x0010, 0x0010, "PN", patient_name);
    w.element(0x0010, 0x0020, "LO", "SYNTHESIZED");
    const Eigen::Vector3d spacing(di.norm(), dj.norm(), dk.norm());
    w.element(0x0018, 0x0050, "DS", ds(spacing.z()));
    w.element(0x0020, 0x000d, "UI", study);
    w.element(0x0020, 0x000e, "UI", series);
    w.element(0x0020, 0x0011, "IS", "1");
    w.element(0x0020, 0x0013, "IS", std::to_string(k + 1));
    const Eigen::Vector3d p = (index_to_mm * Eigen::Vector4d(0, 0, k, 1)).head<3>();
    w.element(0x0020, 0x0032, "DS", ds(p.x()) + "\\" + ds(p.y()) + "\\" + ds(p.z()));
    w.element(0x0020, 0x0037, "DS", ds(row.x()) + "\\" + ds(row.y()) + "\\" + ds(row.z()) + "\\" + ds(column.x()) + "\\" +
                                        ds(column.y()) + "\\" + ds(column.z()));
    w.element(0x0020, 0x0052, "UI", frame);
    w.element(0x0020, 0x1041, "DS", ds(p.z()));
    w.us(0x0028, 0x0002, 1);
    w.element(0x0028, 0x0004, "CS", "MONOCHROME2");
    w.us(0x0028, 0x0010, std::uint16_t(d[1]));  // rows: the j axis
    w.us(0x0028, 0x0011, std::uint16_t(d[0]));  // columns: the i axis
    w.element(0x0028, 0x0030, "DS", ds(spacing.y()) + "\\" + ds(spacing.x()));  // row spacing, column spacing
    w.us(0x0028, 0x0100, 16);
    w.us(0x0028, 0x0101, 16);
    w.us(0x0028, 0x0102, 15);
    w.us(0x0028, 0x0103, 1);  // signed
    w.element(0x0028, 0x1050, "DS", "400");
    w.element(0x0028, 0x1051, "DS", "1800");
    w.element(0x0028, 0x1052, "DS", "0");
    w.element(0x0028, 0x1053, "DS", "1");
    const std::int16_t* plane = voxels + std::size_t(k) * slice.size();
    w.pixels(plane, slice.size());

    char name[32];
    std::snprintf(name, sizeof name, "slice_%04d.dcm", k);
    const std::string path = (fs::path(folder) / name).string();
    std::ofstream out(path, std::ios::binary);
    Writer group;
    group.ul(0x0002, 0x0000, std::uint32_t(meta.bytes().size()));
    out << std::string(128, '\0') << "DICM" << group.bytes() << meta.bytes() << w.bytes();
    if (!out) throw IoError(path + ": write failed");
  }
}

} // namespace hb::datasets
