#pragma once
// The elements of a DICOM file HapticBox needs before a DICOM library reads it: transfer syntax,
// series, image size and pixel format against the pixel data's length, and the geometry tags a
// slice of a volume must have. A pure parser over bytes (no file access, no VTK): the fuzz
// targets run it under the sanitizers.
#include <cstdint>
#include <string>

namespace hb {

/// What check_dicom_header found (text values trimmed of padding).
struct DicomHeader {
  std::string transfer_syntax;       ///< (0002,0010); empty when absent.
  std::string series_uid;            ///< (0020,000E) SeriesInstanceUID.
  std::string photometric;           ///< (0028,0004) PhotometricInterpretation.
  std::string modality;              ///< (0008,0060).
  unsigned rows = 0, columns = 0;    ///< (0028,0010), (0028,0011).
  unsigned bits_allocated = 0;       ///< (0028,0100).
  unsigned samples_per_pixel = 1;    ///< (0028,0002).
  unsigned frames = 1;               ///< (0028,0008) NumberOfFrames.
  std::uint64_t pixel_bytes = 0;     ///< length of (7FE0,0010) PixelData.
  bool has_pixel_data = false;
  bool has_position = false, has_orientation = false, has_spacing = false;
  bool has_rescale_slope = false;
};

/// True when `bytes` (the file's start, at least 132 bytes) has the DICOM preamble: "DICM" at
/// byte 128 (how a file without a .dcm extension is recognised).
bool looks_like_dicom(const std::string& bytes);

/// Parses the whole file `bytes` (preamble, group 2 in explicit VR little endian, then the data
/// set in the transfer syntax's encoding; sequences of defined or undefined length skipped) and
/// checks what a slice of a volume needs: an uncompressed transfer syntax (implicit or explicit
/// VR little endian), Rows, Columns, BitsAllocated (8, 16 or 32), one sample per pixel, a
/// PhotometricInterpretation, ImagePositionPatient, ImageOrientationPatient (two perpendicular
/// unit vectors), PixelSpacing (> 0), PixelData of exactly Rows x Columns x BitsAllocated / 8 bytes,
/// non-empty values where the tags are present (an empty RescaleSlope, TransferSyntaxUID or
/// PhotometricInterpretation crashes VTK's DICOM parser). Throws hb::InvalidInput naming `name`
/// and the element.
DicomHeader check_dicom_header(const std::string& name, const std::string& bytes);

} // namespace hb
