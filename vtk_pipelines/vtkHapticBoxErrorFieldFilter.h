/**
 * @class   vtkHapticBoxErrorFieldFilter
 * @brief   Where on the surface the haptic box is wrong: exact against approximated forces.
 *
 * Input 0: the surface (vtkPolyData with triangles; the mesh the boxes were baked from).
 * Input 1: the boxes (vtkHapticBoxSet, e.g. from vtkHapticBoxBakeFilter output 0).
 * Output: the sample points with point arrays (a thin adapter over hb::compute_error_field):
 *  - "ExactForce", "ApproxForce" (3 components, N): mean forces over the point's probes;
 *  - "AbsoluteForceError" (N): mean |F1 - F0| over all the point's probes
 *    (zero force out of contact), defined everywhere;
 *  - "RelativeForceError": mean |F1 - F0| / |F0| over the probes both answers call a contact
 *    (NaN where none does: no data, not zero error);
 *  - "DirectionError": mean angle between the normals, degrees (NaN likewise);
 *  - "ContactDisagreement": fraction of the point's probes whose contact flags differ;
 *  - "ExactContactFraction": fraction of probes in exact contact;
 *  - "PerceptibleRatio": the largest box-vs-exact difference over its perceptual threshold
 *    among the point's probes (hb::perceive; above 1 a hand would feel it; the active scalars);
 *  - "PerceptibleFraction": fraction of the point's probes whose difference is perceptible;
 *  - "Normals".
 * SampleMode Vertices (default): the output is the triangulated input surface, one value per
 * vertex, plus the cell array "PieceId" (the box of each triangle) for a scene cut into
 * pieces. SampleMode Even: NumberOfSamples points spread evenly by area (vertex cells).
 * Field data: "Units" ("Name: unit" per array; each array also carries UNITS_LABEL), "NoData"
 * (what NaN means), provenance (Boxes, MMin/MMax, NMin/NMax, Codec, Refined, SourceMesh,
 * ProbesPerPoint, Probes, Seed, Stiffness_N_per_m, MetresPerUnit, probe cone and lengths).
 * The exact reference is Embree on the input surface (hb::ExactQuery): the one given with
 * SetExactQuery (the references a session or report already built over the same mesh), or
 * one the filter builds for the update. Field data
 * "ErrorFieldSeconds" holds the computation's wall time. Progress events; abort honoured.
 */
#ifndef vtkHapticBoxErrorFieldFilter_h
#define vtkHapticBoxErrorFieldFilter_h

#include "perception/perceptible.h"
#include "contact/workspace.h"
#include "evaluation/comparison.h"
#include <vtkPolyDataAlgorithm.h>
#include <cstdint>
#include <memory>
#include <string>

namespace hb {
class Communicator;
class ExactQuery;
struct ErrorField;
}

class vtkHapticBoxSet;

class vtkHapticBoxErrorFieldFilter : public vtkPolyDataAlgorithm {
public:
  static vtkHapticBoxErrorFieldFilter* New();
  vtkTypeMacro(vtkHapticBoxErrorFieldFilter, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  enum SampleModes { VERTICES = 0, EVEN = 1 };

  /// Connect the boxes (input port 1).
  void SetBoxSetConnection(vtkAlgorithmOutput* output) { this->SetInputConnection(1, output); }
  void SetBoxSetData(vtkHapticBoxSet* boxes);

  ///@{
  /// Vertices (one value per vertex) or Even (NumberOfSamples area-uniform points).
  vtkSetClampMacro(SampleMode, int, VERTICES, EVEN);
  vtkGetMacro(SampleMode, int);
  void SetSampleModeToVertices() { this->SetSampleMode(VERTICES); }
  void SetSampleModeToEven() { this->SetSampleMode(EVEN); }
  ///@}

  ///@{
  /// Points for SampleMode Even (default 10000).
  vtkSetClampMacro(NumberOfSamples, vtkIdType, 1, VTK_ID_MAX);
  vtkGetMacro(NumberOfSamples, vtkIdType);
  ///@}

  ///@{
  /// Probes aimed at each point (default 1).
  vtkSetClampMacro(ProbesPerPoint, int, 1, 100000);
  vtkGetMacro(ProbesPerPoint, int);
  ///@}

  ///@{
  /// Half-angle of the probe cone around the inward normal, degrees (default 30).
  vtkSetClampMacro(ConeAngle, double, 0.0, 89.0);
  vtkGetMacro(ConeAngle, double);
  ///@}

  ///@{
  /// Probe length and maximal tip depth as fractions of the diagonal (defaults 0.1, 0.03).
  vtkSetClampMacro(LengthFraction, double, 1e-6, 10.0);
  vtkGetMacro(LengthFraction, double);
  vtkSetClampMacro(MaxDepthFraction, double, 0.0, 10.0);
  vtkGetMacro(MaxDepthFraction, double);
  ///@}

  ///@{
  /// Seed of the probe directions and depths (default 1).
  vtkSetMacro(Seed, vtkTypeUInt64);
  vtkGetMacro(Seed, vtkTypeUInt64);
  ///@}

  ///@{
  /// Force law: stiffness in N/m and model units to metres (defaults: the product's stiffness,
  /// hb::WorkspaceOptions::kDefaultStiffness, and 0.001); the front ends set their model's
  /// workspace with SetWorkspace.
  vtkSetClampMacro(Stiffness, double, 1e-12, VTK_DOUBLE_MAX);
  vtkGetMacro(Stiffness, double);
  vtkSetClampMacro(MetresPerUnit, double, 1e-12, VTK_DOUBLE_MAX);
  vtkGetMacro(MetresPerUnit, double);
  /// Stiffness, MetresPerUnit and MaxForce from the model's workspace (the scale every front end
  /// computes forces at; hb::Workspace::law gives the same law).
  void SetWorkspace(const hb::Workspace& workspace);
  /// Largest force the device renders, N (forces are judged clamped to it; default 8).
  vtkSetClampMacro(MaxForce, double, 1e-6, VTK_DOUBLE_MAX);
  vtkGetMacro(MaxForce, double);
  /// What a hand tells apart (hb::perceive): the PerceptibleRatio and PerceptibleFraction
  /// arrays judge against these (default: nominal).
  void SetPerceptualThresholds(const hb::PerceptualThresholds& t) {
    this->Thresholds = t;
    this->Modified();
  }
  const hb::PerceptualThresholds& GetPerceptualThresholds() const { return this->Thresholds; }
  /// The force law, the force limit and the thresholds of a model's workspace and judgement
  /// (Stiffness, MetresPerUnit, MaxForce, PerceptualThresholds): what every front end sets.
  void SetWorkspace(const hb::Workspace& workspace, const hb::PerceptualJudge& judge) {
    this->SetWorkspace(workspace);
    this->SetPerceptualThresholds(judge.thresholds);
  }
  ///@}

  ///@{
  /// The ranks sharing the field, as VTK's parallel filters take a controller (default null:
  /// this process alone; not owned). With several ranks every rank runs the filter on the same
  /// input; the points are shared out and only rank 0's output carries the arrays (the other
  /// ranks output the points alone).
  void SetCommunicator(hb::Communicator* communicator) { this->Communicator = communicator; }
  hb::Communicator* GetCommunicator() const { return this->Communicator; }

  /// The exact reference to compare with, built over the input surface's mesh (same vertices
  /// and triangles; the update fails naming both counts otherwise), shared and kept alive by
  /// the filter; null (the default): the filter builds its own Embree scene each update.
  void SetExactQuery(std::shared_ptr<const hb::ExactQuery> exact);
  std::shared_ptr<const hb::ExactQuery> GetExactQuery() const { return this->Exact; }
  /// True when the last update built its own Embree scene (no exact query was set).
  bool GetBuiltExact() const { return this->BuiltExact; }

  /// The field of the last successful update (its per-point figures are the output's arrays;
  /// probes and seconds besides), or nullptr. For front ends that show its summary.
  const hb::ErrorField* GetErrorField() const { return this->Field.get(); }
  /// Why the last update failed (as vtkErrorMacro reported it, without its prefix), or empty.
  const std::string& GetLastError() const { return this->LastError; }
  ///@}

protected:
  vtkHapticBoxErrorFieldFilter();
  ~vtkHapticBoxErrorFieldFilter() override;
  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  int SampleMode = VERTICES;
  vtkIdType NumberOfSamples = 10000;
  int ProbesPerPoint = 1;
  double ConeAngle = 30.0;
  double LengthFraction = 0.10;
  double MaxDepthFraction = 0.03;
  vtkTypeUInt64 Seed = 1;
  double Stiffness = hb::WorkspaceOptions::kDefaultStiffness;
  double MetresPerUnit = 0.001;
  double MaxForce = hb::WorkspaceOptions::kDefaultMaxForce;
  hb::PerceptualThresholds Thresholds;
  hb::Communicator* Communicator = nullptr;
  std::shared_ptr<const hb::ExactQuery> Exact;
  bool BuiltExact = false;
  std::unique_ptr<hb::ErrorField> Field;
  std::string LastError;

private:
  vtkHapticBoxErrorFieldFilter(const vtkHapticBoxErrorFieldFilter&) = delete;
  void operator=(const vtkHapticBoxErrorFieldFilter&) = delete;
};

#endif
