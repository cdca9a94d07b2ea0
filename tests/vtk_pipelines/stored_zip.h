#pragma once
// A zip archive of stored (uncompressed) entries, and a 3MF package of one model part built on
// it: the tests write 3MF files with exactly the XML they want to damage.
#include <zlib.h>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace hb::test {

// A zip archive of stored (uncompressed) entries, as a 3MF file is.
inline std::string stored_zip(const std::vector<std::pair<std::string, std::string>>& entries) {
  std::string out, central;
  auto u16 = [](std::string& s, unsigned v) { s += char(v & 255), s += char(v >> 8 & 255); };
  auto u32 = [](std::string& s, std::uint32_t v) { for (int i = 0; i < 4; ++i) s += char(v >> (8 * i) & 255); };
  for (const auto& [name, data] : entries) {
    const std::uint32_t crc = std::uint32_t(crc32(0, reinterpret_cast<const Bytef*>(data.data()), uInt(data.size())));
    const std::uint32_t offset = std::uint32_t(out.size());
    u32(out, 0x04034b50); u16(out, 20); u16(out, 0); u16(out, 0); u16(out, 0); u16(out, 0);
    u32(out, crc); u32(out, std::uint32_t(data.size())); u32(out, std::uint32_t(data.size()));
    u16(out, unsigned(name.size())); u16(out, 0);
    out += name + data;
    u32(central, 0x02014b50); u16(central, 20); u16(central, 20); u16(central, 0); u16(central, 0); u16(central, 0); u16(central, 0);
    u32(central, crc); u32(central, std::uint32_t(data.size())); u32(central, std::uint32_t(data.size()));
    u16(central, unsigned(name.size())); u16(central, 0); u16(central, 0); u16(central, 0); u16(central, 0);
    u32(central, 0); u32(central, offset);
    central += name;
  }
  const std::uint32_t at = std::uint32_t(out.size());
  out += central;
  u32(out, 0x06054b50); u16(out, 0); u16(out, 0); u16(out, unsigned(entries.size())); u16(out, unsigned(entries.size()));
  u32(out, std::uint32_t(central.size())); u32(out, at); u16(out, 0);
  return out;
}

inline std::string three_mf(const std::string& model) {
  return stored_zip({{"[Content_Types].xml",
                      "<?xml version=\"1.0\"?><Types xmlns=\"http://schemas.openxmlformats.org/package/2006/content-types\">"
                      "<Default Extension=\"model\" ContentType=\"application/vnd.ms-package.3dmanufacturing-3dmodel+xml\"/></Types>"},
                     {"_rels/.rels",
                      "<?xml version=\"1.0\"?><Relationships xmlns=\"http://schemas.openxmlformats.org/package/2006/relationships\">"
                      "<Relationship Target=\"/3D/3dmodel.model\" Id=\"rel0\" "
                      "Type=\"http://schemas.microsoft.com/3dmanufacturing/2013/01/3dmodel\"/></Relationships>"},
                     {"3D/3dmodel.model", model}});
}

} // namespace hb::test
