#pragma once
/// What a run is computed from, as a checkpoint records it: the scene's values and the bytes of
/// every file the scene reads, part by part, so that a checkpoint of another scene (or of this one
/// before an edit) is refused with the part that changed named.
#include "granular/checkpoint.hpp"
#include "granular/scene.hpp"

namespace granular {

/// The scene's parts, in this order and under these keys: "material", "simulation", "box",
/// "particles[i]" for each entry, "total_mass", "stages[i]" for each stage, "output". A part's
/// hash covers every value of it that the run uses, numbers by their bits: a comment, the layout
/// or the order of keys in the TOML file change none, and neither does moving the files. A CSV
/// entry's hash is of the values its rows give, as loadScene read them (CsvGenerator::contentHash),
/// or read now for a scene built in C++. Throws CheckpointError if such a file cannot be read.
SceneFingerprint fingerprintScene(const Scene& scene);

}  // namespace granular
