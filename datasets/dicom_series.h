#pragma once
// Writes a signed 16-bit CT volume as a DICOM series (one file per slice, CT Image Storage,
// explicit VR little endian, uncompressed), for the generated test data: the femur CT as a
// scanner would hand it over. Slice k's ImagePositionPatient is index_to_mm * (0, 0, k); rows
// follow the j axis, columns the i axis; the world frame's numbers are kept as they are (the
// series reads back at the same millimetre coordinates, in DICOM's LPS frame).
#include <Eigen/Core>
#include <string>

class vtkImageData;

namespace hb::datasets {

/// Writes `image` (VTK_SHORT, index space) into `folder` as slice_0000.dcm, slice_0001.dcm, ...
/// Throws hb::IoError when a file cannot be written.
void write_dicom_series(vtkImageData* image, const Eigen::Matrix4d& index_to_mm, const std::string& folder,
                        const std::string& patient_name, const std::string& description);

} // namespace hb::datasets
