#pragma once
// A recorded servo trajectory as a ParaView polyline: the log's device positions mapped back
// into the model's frame (the servo loop's Workspace), written as VTK XML PolyData.
#include "device/servo_log.h"
#include "device/servo_loop.h"
#include <string>

namespace hb::cli {

/// Refuses a log no device could have recorded: a time, position, force or depth that is not
/// finite, or a force beyond the device's peak force (the records hold the force after the
/// safety layer). Throws hb::InvalidInput naming `source`, the record and the field.
void check_trajectory_records(const ServoLog& log, const std::string& source);

/// Writes `log` as a polyline .vtp at `path` (point arrays Time s, Force N, ForceMagnitude N,
/// Depth, Contact, QueryTime ns, SafetyFlags; field data: rate, the workspace's model origin
/// and model units per metre, version). Tips are in model units: workspace.to_model(position).
/// Throws hb::IoError. Returns the number of points written.
std::size_t write_trajectory_vtp(const ServoLog& log, const Workspace& workspace, const std::string& source,
                                 const std::string& path);

} // namespace hb::cli
