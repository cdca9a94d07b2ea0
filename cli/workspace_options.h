#pragma once
// The one scale every figure is judged at (hb::Workspace) and how differences are judged
// (hb::PerceptualJudge), as the options of every command that computes forces give them:
// --workspace mm=D|real-size|metres-per-unit=S,stiffness=K,max-force=F and --perceptual.
#include "contact/workspace.h"
#include "evaluation/comparison.h"
#include <CLI/CLI.hpp>
#include <string>

namespace hb::cli {

struct WorkspaceArgs {
  WorkspaceOptions given;  ///< --workspace (hb::parse_workspace_spec)
  std::string perceptual = "nominal";

  WorkspaceOptions options() const { return given; }
  /// The workspace of a model of this diagonal (model units).
  Workspace workspace(double model_diagonal) const;
  /// The thresholds (--perceptual) and the force limit.
  PerceptualJudge judge() const;
};

/// Adds the workspace and judgement options to a command: --workspace (mm, real-size or
/// metres-per-unit; stiffness, max-force) and --perceptual.
void add_workspace_options(CLI::App& cmd, WorkspaceArgs& args);

} // namespace hb::cli
