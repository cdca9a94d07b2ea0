#pragma once
// A volume file's data held to its header before VTK reads it: the size the header claims
// against the voxel limit, and the bytes (raw, gzip, zlib or text; inline, in a data file or a
// NIfTI .img) against the size it declares. VTK's readers trust the header: a truncated or
// altered file would be read as garbage or past its end.
#include "formats/volume_headers.h"
#include <cstddef>
#include <string>

namespace hb::vtk {

/// The first `n` bytes of a file (of its decompressed content when `gz`). Throws hb::IoError
/// (cannot open) or hb::InvalidInput (a damaged gzip stream).
std::string file_head(const std::string& path, std::size_t n, bool gz);

/// Throws hb::InvalidInput naming `path` when the VTK extent is empty or holds more than
/// `max_voxels` voxels.
void check_size(const std::string& path, const int* extent, std::size_t max_voxels);

/// Holds the data (inline or in data files beside `name`) of a MetaImage or NRRD header's
/// `layout` to what it declares; throws hb::InvalidInput naming the file and the shortfall
/// or surplus.
void check_volume_data(const std::string& name, const VolumeLayout& layout, std::size_t max_voxels);

/// The same for a NIfTI file (.nii, .nii.gz, or a .hdr with its .img).
void check_nifti_file(const std::string& path, std::size_t max_voxels);

} // namespace hb::vtk
