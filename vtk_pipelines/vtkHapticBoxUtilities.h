/**
 * @class   vtkHapticBoxUtilities
 * @brief   Conversions between VTK data and the HapticBox core (the one place they live).
 *
 * Model: VTK's Filters/OpenTURNS vtkOTUtilities. Every filter of hb::vtk converts its input
 * with ToTriangleMesh, calls one core function and converts back with ToPolyData and the
 * array helpers. Cell ids of a polydata made by ToPolyData are the core's triangle ids.
 */
#ifndef vtkHapticBoxUtilities_h
#define vtkHapticBoxUtilities_h

#include "decomposition/auto_decomposition.h"
#include "mesh/triangle_mesh.h"
#include "progress.h"
#include <vtkSmartPointer.h>
#include <string>
#include <vector>

namespace hb {
class BoxScene;
}
class vtkAlgorithm;
class vtkFloatArray;
class vtkPolyData;

class vtkHapticBoxUtilities {
public:
  /**
   * The polygons and triangle strips of `polyData` as a core triangle mesh (polygons are
   * fan-triangulated, triangles with a repeated index dropped; vertices and lines ignored).
   * Point normals are taken from the point data's normals when present with one tuple per
   * point (normalised; a normal already of unit length is kept bit for bit, so a core mesh
   * through ToPolyData and back is the same mesh), otherwise computed as the core does
   * (area-weighted).
   * Throws hb::InvalidInput on a null input, NaN/Inf coordinates or no triangles.
   */
  static hb::TriangleMesh ToTriangleMesh(vtkPolyData* polyData);

  /// A triangle polydata (cell i = triangle i) with the vertex normals as point "Normals".
  static vtkSmartPointer<vtkPolyData> ToPolyData(const hb::TriangleMesh& mesh);

  /// The PBB outlines of a scene: 8 corners and 12 lines per box, cell data "BoxId".
  static vtkSmartPointer<vtkPolyData> BoxOutlines(const hb::BoxScene& scene);

  /// A float array of 3-component tuples named `name`.
  static vtkSmartPointer<vtkFloatArray> ToVectorArray(const char* name, const std::vector<hb::Vec3>& values);

  /// A float array of scalars named `name`.
  static vtkSmartPointer<vtkFloatArray> ToScalarArray(const char* name, const std::vector<float>& values);

  /**
   * A core progress callback for `algorithm`: forwards the fraction to UpdateProgress (only
   * when called on the thread that made the callback, since VTK observers expect the
   * pipeline's thread) and returns false once AbortExecute is set, which cancels the core
   * operation (it throws hb::Cancelled). `begin`/`end` map the fraction into a sub-range.
   */
  static hb::ProgressCallback MakeProgressCallback(vtkAlgorithm* algorithm, double begin = 0.0, double end = 1.0);

  /// The text that names a decomposition's options (every field that changes its pieces):
  /// vtkHapticBoxDecompositionFilter writes it on its output as field data
  /// "DecompositionOptions", and vtkHapticBoxBakeFilter reads it to know that the input's
  /// "PieceId" are the pieces its automatic recipe asks for.
  static std::string DecompositionSignature(const hb::AutoDecompositionOptions& options);

  /// Lower-case extension of a path, with the dot (".off"), or empty.
  static std::string Extension(const std::string& path);
};

#endif
