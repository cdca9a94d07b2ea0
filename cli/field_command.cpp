// hapticbox field MESH|BOX [MESH] -o FIELD.vtp [--m M --n N] [--probes K] [--even N] [--seed S]
// The error field through the VTK pipeline (reader -> bake or loaded boxes -> error-field
// filter -> XML writer): the same arrays the desktop window shows, for ParaView or scripts.
// Field data carries the units and the provenance (box, densities, probes, seed, force law,
// version); the box outlines go to FIELD_boxes.vtp beside it (cell data PieceId, M, N).
#include "cli_support.h"
#include "commands.h"
#include "errors.h"
#include "haptic_box/box_file.h"
#include "vtkHapticBoxBakeFilter.h"
#include "vtkHapticBoxErrorFieldFilter.h"
#include "vtkHapticBoxMeshReader.h"
#include "vtkHapticBoxSet.h"
#include "polydata_files.h"
#include "figure_text.h"
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
    int m = 32, n = 16, probes = 1;
    vtkIdType even = 0;
    std::uint64_t seed = 1;
    hb::ForceLaw law;
  };
  auto opts = std::make_shared<Opts>();
  hb::cli::add_model_options(*cmd, opts->model);
  cmd->add_option("INPUT", opts->inputs, "MESH (baked here), or BOX MESH")->required()->expected(1, 2);
  cmd->add_option("-o,--output", opts->out, "Output .vtp file")->required();
  cmd->add_option("-m,--m", opts->m, "Position density m when baking")->check(CLI::Range(2, 4096))->capture_default_str();
  cmd->add_option("-n,--n", opts->n, "Directional density n when baking")->check(CLI::Range(2, 1024))->capture_default_str();
  cmd->add_option("--probes", opts->probes, "Probes per point")->check(CLI::Range(1, 100000))->capture_default_str();
  cmd->add_option("--even", opts->even, "Sample N points evenly instead of the vertices")->check(CLI::Range(vtkIdType(1), vtkIdType(100000000)));
  cmd->add_option("--seed", opts->seed, "Probe seed")->capture_default_str();
  hb::cli::add_force_law_options(*cmd, opts->law);
  cmd->callback([opts] {
    const bool with_box = hb::cli::is_box_file(opts->inputs[0]);
    if (with_box && opts->inputs.size() != 2) throw hb::cli::UsageError("give BOX then MESH");
    if (!with_box && opts->inputs.size() != 1) throw hb::cli::UsageError("give MESH alone, or BOX then MESH");
    const std::string mesh_path = with_box ? opts->inputs[1] : opts->inputs[0];
    vtkNew<vtkHapticBoxMeshReader> reader;
    reader->SetFileName(mesh_path.c_str());
    reader->SetModelOptions(hb::cli::to_model_options(opts->model));
    reader->Update();
    if (reader->GetOutput()->GetNumberOfPoints() == 0) throw hb::InvalidInput(mesh_path + ": could not read the mesh");
    vtkNew<vtkHapticBoxErrorFieldFilter> field;
    field->SetInputConnection(reader->GetOutputPort());
    vtkNew<vtkHapticBoxBakeFilter> bake;
    vtkNew<vtkHapticBoxSet> loaded;
    double bake_seconds = 0.0;
    if (with_box) {
      loaded->SetScene(std::make_shared<const hb::BoxScene>(hb::load_box_file(opts->inputs[0])));
      field->SetBoxSetData(loaded);
    } else {
      bake->SetInputConnection(reader->GetOutputPort());
      hb::BakeRecipe recipe = bake->GetRecipe();
      recipe.options.params.m = opts->m;
      recipe.options.params.n = opts->n;
      // Baked across the ranks of an MPI job; every rank queries the boxes for its points.
      recipe.options.communicator = &hb::cli::communicator();
      recipe.options.scene_on_every_rank = true;
      bake->SetRecipe(recipe);
      bake->Update();
      if (!bake->GetBoxSet() || bake->GetBoxSet()->GetNumberOfBoxes() == 0) throw hb::Error("the bake failed");
      bake_seconds = bake->GetBakeSeconds();
      field->SetBoxSetConnection(bake->GetOutputPort(0));
    }
    // The points are dealt across the ranks of an MPI job; rank 0 gets the whole field.
    field->SetCommunicator(&hb::cli::communicator());
    field->SetProbesPerPoint(opts->probes);
    field->SetSeed(opts->seed);
    field->SetStiffness(opts->law.stiffness_n_per_m);
    field->SetMetresPerUnit(opts->law.metres_per_unit);
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
                   {"BoxFile", with_box ? opts->inputs[0] : std::string("(baked by field, not saved)")}};
      if (!with_box) p.numbers = {{"BakeSeconds", bake_seconds}};
      hb::vtk::add_provenance(out->GetFieldData(), p);
    }
    hb::vtk::write_polydata_xml(out, opts->out);
    const hb::BoxScene& scene = with_box ? *loaded->GetScene() : *bake->GetBoxSet()->GetScene();
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
    std::cout << "boxes " << outlines_path << ": " << scene.boxes().size() << " box outline(s)\n";
  });
}
