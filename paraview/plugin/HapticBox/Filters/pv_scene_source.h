#pragma once
// Where the ParaView filters get their boxes: a .hbox file (loaded once per file and
// modification time) or, without one, the default bake of the input surface
// (vtkHapticBoxBakeFilter with hb::default_recipe(), as `hapticbox bake`). And the workspace of
// the input's diagonal from the filters' text properties, as the command line reads its options.
#include "contact/workspace.h"
#include "evaluation/comparison.h"
#include "scene/box_scene.h"
#include <memory>
#include <string>

#include <vtkSmartPointer.h>

class vtkInformationVector;
class vtkPolyData;

namespace hb::paraview {

/// The polydata on input port 0, shallow-copied: the input of an inner vtk_pipelines filter that
/// leaves ParaView's pipeline object untouched.
vtkSmartPointer<vtkPolyData> input_surface(vtkInformationVector** inputVector);

/// The scene of `box_file` (empty: the default bake of `surface`). Throws hb::Error naming the
/// file and the cause.
std::shared_ptr<const BoxScene> scene_for(const std::string& box_file, vtkPolyData* surface);

/// The workspace of a model of this diagonal (`spec`: hb::parse_workspace_spec, empty for the
/// default) and the judge of `perceptual` (hb::parse_thresholds) with its force limit.
Workspace workspace_for(double model_diagonal, const std::string& spec);
PerceptualJudge judge_for(const std::string& workspace_spec, const std::string& perceptual);

} // namespace hb::paraview
