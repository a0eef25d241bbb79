#pragma once
// The command line of a scene with a volume and surfaces (`render VOLUME SURFACE...`): which files
// are which, the volume's options (volume_options.hpp), the surfaces' mode, and the camera that
// frames both. InputError names the option or file at fault.
#include <optional>
#include <string>
#include <vector>

#include "app/common/cli_args.hpp"
#include "app/common/volume_options.hpp"
#include "scene/camera.hpp"
#include "scene/surface_scene.hpp"

namespace prismoid::app {

// Whether `args` (a verb's, args[0] the verb) names both a volume and a surface among its
// files; a word after an option other than one of `flags` is that option's value.
bool names_mixed_scene(const std::vector<std::string>& args, const std::vector<std::string>& flags);

// Whether `files` holds both a volume and a surface (a surface file, cornell-box, furnace:...).
bool files_mix_kinds(const std::vector<std::string>& files);

// The options a mixed scene takes beyond the volume's (kVolumeOptions): the surfaces' mode, spelt
// for the surfaces as --mode is for the volume so that one option table can hold both, and
// whether they cast shadows (on|off, the spelling every surface mode will share).
inline const std::vector<std::string> kMixedSceneOptions = {"surface-mode", "shadows"};

struct MixedScene {
  VolumeChoice volume;                  // the one volume file (several: InputError)
  Camera camera;                        // the camera options over the bounds of the volume and the surfaces together
  SurfaceScene surfaces;                // every surface file's meshes, materials and lights, in order; lit
                                        // (with_default_lighting from `camera`) where they bring no light
  std::string surface_mode = "forward"; // --surface-mode: any GPU surface mode
  std::optional<bool> shadows;          // --shadows on|off; none: the surface renderer's default
  // Whether the surfaces cast shadows when --shadows is not given, on a device that traces rays
  // (a light or an emitter that casts them): what the CPU reference and the plan assume.
  bool default_shadows = false;
};

// The scene `a` names (a.files: a volume and surfaces): the volume loaded through volume_choice,
// the surfaces read and lit, the camera. A surface mode given to --mode, a volume mode that
// follows no depth limit (or the reference of an analytic field), a surface mode that is not composited with a volume
// (the CPU path tracer), --shadows other than on or off,
// several volumes: refused, each saying what to use instead.
MixedScene mixed_scene_from(const ParsedArgs& a);

}  // namespace prismoid::app
