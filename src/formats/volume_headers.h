#pragma once
// Headers of the volume formats HapticBox reads through third-party libraries (NIfTI,
// MetaImage, NRRD), checked before the library sees the file: the sizes, element type,
// encoding and data files they declare, so that the caller can hold the data against them (a
// short or truncated volume is an error, never zeros). Pure functions over bytes (no file
// access, no VTK): the fuzz targets run them under the sanitizers.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace hb {

/// Where a volume's voxels are and how many bytes they must fill.
struct VolumeLayout {
  std::array<std::uint64_t, 4> sizes{{1, 1, 1, 1}};  ///< voxels along each axis (4th: time or channels).
  unsigned bytes_per_element = 0;                     ///< one stored value.
  unsigned components = 1;                            ///< values per voxel.
  /// "raw", "gzip" (a gzip stream), "zlib" (MetaImage CompressedData: a zlib stream) or "text"
  /// (numbers separated by white space).
  std::string encoding = "raw";
  /// Inline data: where the (encoded) data starts in the header file (NIfTI: vox_offset, in
  /// the decompressed content of a .nii.gz). Data files: 0.
  std::uint64_t data_offset = 0;
  /// Bytes skipped at the start of the decoded data (MetaImage HeaderSize, NRRD byte skip).
  std::uint64_t skip = 0;
  /// NRRD "byte skip: -1": the data is the last expected_bytes() of the (raw) data.
  bool data_at_end = false;
  /// Data files, relative to the header's folder, in order; empty: the data follows the header.
  std::vector<std::string> data_files;
  /// sizes x components x bytes_per_element (the decoded data's length).
  std::uint64_t expected_bytes() const;
  /// sizes' product (voxels of the whole volume, all time points).
  std::uint64_t voxels() const;
};

/// A NIfTI-1 (348-byte) or NIfTI-2 (540-byte) header, either byte order: sizeof_hdr, magic
/// ("n+1"/"n+2" single file, "ni1"/"ni2" header and image pair), dim (1 to 7 axes, each >= 1),
/// datatype (a scalar type, bitpix matching), pixdim of the three spatial axes (finite, > 0),
/// vox_offset (>= 352 or 544 in a single file, whole), scl_slope and scl_inter finite (the
/// offset only where the slope is not 0). `header` holds at least the header's
/// bytes (after decompression). Throws hb::InvalidInput naming `name` and the field.
VolumeLayout check_nifti_header(const std::string& name, const std::string& header);

/// A MetaImage header (`text` from the file's start; .mha holds its data after it, .mhd names
/// its data file): NDims (2 to 4), DimSize (NDims sizes >= 1), ElementType, channels, BinaryData,
/// CompressedData, HeaderSize, ElementDataFile (LOCAL, a file, LIST, or a pattern
/// "fmt first last step" with a step that reaches `last`). Throws hb::InvalidInput naming `name`.
VolumeLayout check_metaimage_header(const std::string& name, const std::string& text);

/// A NRRD header (`text` from the file's start, magic NRRD000N): type, dimension (1 to 4; a
/// leading axis of 1 to 4 values is channels), sizes, encoding (raw, gzip, text), endian, byte
/// and line skip, data file (a file, LIST, or a pattern "fmt first last step"). Throws
/// hb::InvalidInput naming `name` and the field.
VolumeLayout check_nrrd_header(const std::string& name, const std::string& text);

} // namespace hb
