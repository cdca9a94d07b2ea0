#pragma once
// A model's loader options as every front end takes them in text: the unit, the volume's
// surface spec (`iso=V|label=L,smooth=N,triangles=N`) and the CAD tessellation spec
// (`chordal-mm=D,force-tolerance=N,accept-lost-faces`). The command line (`--unit`, `--volume`,
// `--cad`), the window and the Python module (`hapticbox.Model(path, unit=, volume=, cad=)`) all
// read them here, so the same words give the same surface and the same model hash.
#include "model_loader.h"
#include <string>

namespace hb::vtk {

/// The option's value as the help shows it.
inline constexpr const char* kCadSpecSyntax = "chordal-mm=D,force-tolerance=N,accept-lost-faces";

/// Reads "chordal-mm=D,force-tolerance=N,accept-lost-faces" (any subset, any order) into `cad`
/// (keys not given keep their value): chordal-mm in [0, 1e30] mm (0: derived from the force
/// tolerance), force-tolerance in [1e-30, 1e30] N, accept-lost-faces a flag (bare, =on/off).
/// Throws hb::InvalidInput naming "--cad" and the key: an unknown key, a bad value.
void parse_cad_spec(const std::string& spec, CadOptions& cad);

/// The loader's options for the three texts (empty: the default). The unit is checked by
/// mm_per_unit. Throws hb::InvalidInput naming the option, the key and the bad value.
ModelOptions model_options_from_specs(const std::string& unit, const std::string& volume, const std::string& cad);

/// load_model, with an allocation that no memory can meet (a damaged size in the file) turned
/// into hb::InvalidInput naming the file, never a bare std::bad_alloc or std::length_error.
LoadedModel load_model_guarded(const std::string& path, const ModelOptions& options = {});

} // namespace hb::vtk
