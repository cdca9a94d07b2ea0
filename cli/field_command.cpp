// hapticbox field MESH|BOX [MESH] -o FIELD.vtp [--m M --n N] [--probes K] [--even N] [--seed S]
// The error field through the VTK pipeline (the model loader -> boxes -> error-field filter -> XML
// writer): the same arrays the desktop window shows, for ParaView or scripts. From a MESH the
// boxes are the default bake through the box cache (as `report` and the window make them), or
// one raw box of the sampling -m / -n asks for. Forces at the model's workspace scale; the
// active array is PerceptibleRatio (the difference over what a hand can feel).
// Field data carries the units and the provenance (box, densities, probes, seed, force law,
// version); the box outlines go to FIELD_boxes.vtp beside it (cell data PieceId, M, N).
#include "cli_support.h"
#include "commands.h"
#include "errors.h"
#include "evaluation/error_field.h"
#include "haptic_box/box_file.h"
#include "vtkHapticBoxErrorFieldFilter.h"
#include "vtkHapticBoxUtilities.h"
#include "vtkHapticBoxSet.h"
#include "polydata_files.h"
#include "figure_text.h"
#include "perceptible_text.h"
#include "recipe/box_cache.h"
#include "mesh/mesh_io.h"
#include <vtkDataArray.h>
#include <vtkFieldData.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>

void add_field_command(CLI::App& app) {
  auto* cmd = app.add_subcommand("field", "Compute the error field over a surface and write it as VTP");
  struct Opts {
    hb::cli::ModelArgs model;
    std::vector<std::string> inputs;
    std::string out;
    hb::BoxParams params;
    int probes = 1;
    vtkIdType even = 0;
    std::uint64_t seed = 1;
    hb::cli::WorkspaceArgs workspace;
    std::string cache;
  };
  auto opts = std::make_shared<Opts>();
  hb::cli::add_model_options(*cmd, opts->model);
  cmd->add_option("INPUT", opts->inputs, "MESH (baked here), or BOX MESH")->required()->expected(1, 2);
  cmd->add_option("-o,--output", opts->out, "Output .vtp file")->required();
  cmd->add_option("-m,--m", opts->params.m, "Bake one raw box of this position density instead of the default bake")
      ->check(CLI::Range(2, 4096));
  cmd->add_option("-n,--n", opts->params.n, "Bake one raw box of this directional density instead of the default bake")
      ->check(CLI::Range(2, 1024));
  hb::cli::add_cache_option(*cmd, opts->cache);
  cmd->add_option("--probes", opts->probes, "Probes per point")->check(CLI::Range(1, 100000))->capture_default_str();
  cmd->add_option("--even", opts->even, "Sample N points evenly instead of the vertices")->check(CLI::Range(vtkIdType(1), vtkIdType(100000000)));
  cmd->add_option("--seed", opts->seed, "Probe seed")->capture_default_str();
  hb::cli::add_workspace_options(*cmd, opts->workspace);
  cmd->callback([opts, cmd] {
    const bool with_box = hb::cli::is_box_file(opts->inputs[0]);
    if (with_box && opts->inputs.size() != 2) throw hb::cli::UsageError("give BOX then MESH");
    if (!with_box && opts->inputs.size() != 1) throw hb::cli::UsageError("give MESH alone, or BOX then MESH");
    const std::string mesh_path = with_box ? opts->inputs[1] : opts->inputs[0];
    // Read once: the surface the field is measured on and, from a MESH, the one baked.
    const hb::TriangleMesh mesh = hb::cli::load_mesh(mesh_path, opts->model);
    if (mesh.triangle_count() == 0) throw hb::InvalidInput(mesh_path + ": could not read the mesh");
    vtkNew<vtkHapticBoxErrorFieldFilter> field;
    field->SetInputData(vtkHapticBoxUtilities::ToPolyData(mesh));
    vtkNew<vtkHapticBoxSet> loaded;
    double bake_seconds = 0.0;
    std::string box_label;
    if (with_box) {
      loaded->SetScene(std::make_shared<const hb::BoxScene>(hb::load_box_file(opts->inputs[0])));
      box_label = opts->inputs[0];
    } else {
      const hb::SamplingGiven sampling = hb::cli::sampling_given(*cmd);
      const bool sampling_given = !hb::bakes_default_recipe(sampling);
      hb::cli::ModelBake baked = hb::cli::bake_model(mesh, mesh_path, hb::cli::hash_model(mesh_path, opts->model),
                                                     sampling, opts->params, opts->cache);
      bake_seconds = baked.seconds;
      box_label = baked.from_cache ? baked.cache_path + " (the default bake, from the box cache)"
                  : sampling_given ? "(one raw box m" + std::to_string(opts->params.m) + " n" +
                                         std::to_string(opts->params.n) + ", baked by field, not saved)"
                                   : "(the default bake, baked by field" +
                                         std::string(baked.cache_path.empty() ? ", not saved)" : ", cached)");
      loaded->SetScene(std::make_shared<const hb::BoxScene>(std::move(baked.scene)));
    }
    field->SetBoxSetData(loaded);
    const hb::BoxScene& scene = *loaded->GetScene();
    const hb::Workspace ws = opts->workspace.workspace(mesh.bounds().diagonal());  // as eval
    const hb::PerceptualJudge judge = opts->workspace.judge();
    // The points are dealt across the ranks of an MPI job; rank 0 gets the whole field.
    field->SetCommunicator(&hb::cli::communicator());
    field->SetProbesPerPoint(opts->probes);
    field->SetSeed(opts->seed);
    field->SetWorkspace(ws);
    field->SetPerceptualThresholds(judge.thresholds);
    if (opts->even > 0) {
      field->SetSampleModeToEven();
      field->SetNumberOfSamples(opts->even);
    }
    const auto t0 = std::chrono::steady_clock::now();
    field->Update();
    const double filter_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (!hb::cli::communicator().is_root()) return;  // rank 0 holds the field and writes it
    vtkPolyData* out = field->GetOutput();
    if (!out->GetPointData()->GetArray("RelativeForceError")) throw hb::Error("the error field failed");
    {
      hb::vtk::Provenance p;
      p.strings = {{"HapticBoxVersion", HB_VERSION},
                   {"Mesh", mesh_path},
                   {"BoxFile", box_label},
                   {"Workspace", ws.describe()},
                   {"Perceptual", hb::thresholds_spec(judge.thresholds)}};
      if (!with_box) p.numbers = {{"BakeSeconds", bake_seconds}};
      hb::vtk::add_provenance(out->GetFieldData(), p);
    }
    hb::vtk::write_polydata_xml(out, opts->out);
    std::string outlines_path = opts->out;
    if (hb::cli::lower_extension(outlines_path) == ".vtp") outlines_path.resize(outlines_path.size() - 4);
    outlines_path += "_boxes.vtp";
    vtkSmartPointer<vtkPolyData> outlines = hb::vtk::box_outline_polydata(scene);
    hb::vtk::add_provenance(outlines->GetFieldData(), {{{"HapticBoxVersion", HB_VERSION}, {"Mesh", mesh_path}}, {}});
    hb::vtk::write_polydata_xml(outlines, outlines_path);
    std::vector<double> errors;
    vtkDataArray* err = out->GetPointData()->GetArray("RelativeForceError");
    for (vtkIdType i = 0; i < err->GetNumberOfTuples(); ++i)
      if (!std::isnan(err->GetComponent(i, 0))) errors.push_back(err->GetComponent(i, 0));
    std::sort(errors.begin(), errors.end());
    const double core_seconds = out->GetFieldData()->GetArray("ErrorFieldSeconds")->GetComponent(0, 0);
    std::cout << "field " << opts->out << ": " << out->GetNumberOfPoints() << " points, " << opts->probes
              << " probe(s) each; error field " << hb::sig(core_seconds) << " s (filter "
              << hb::sig(filter_seconds) << " s)";
    if (!with_box) std::cout << ", bake " << hb::sig(bake_seconds) << " s";
    if (!errors.empty())
      std::cout << "; relative force error median " << hb::sig(100.0 * errors[errors.size() / 2]) << " %, p95 "
                << hb::sig(100.0 * errors[std::size_t(0.95 * double(errors.size() - 1))]) << " %";
    std::cout << "; " << (out->GetNumberOfPoints() - vtkIdType(errors.size())) << " points with no data (NaN)\n";
    const hb::ErrorField* f = field->GetErrorField();
    std::size_t felt = 0;
    for (float v : f->perceptible_fraction) felt += v > 0.f;
    std::cout << "  perceptible: " << felt << " of " << f->size() << " points have a probe a hand would tell apart ("
              << hb::percent(f->size() ? double(felt) / double(f->size()) : 0.0) << "; threshold "
              << hb::thresholds_text(judge.thresholds) << ")\n  workspace: " << ws.describe() << "\n";
    std::cout << "boxes " << outlines_path << ": " << scene.parts().boxes.size() << " box outline(s)\n";
  });
}
