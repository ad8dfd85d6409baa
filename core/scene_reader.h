#pragma once
// Reads a scene JSON file (docs/SCENES.md) into a SceneDesc. Every error names the file and the
// field ("objects[1].material.opacity") or the line and column of a syntax error.

#include <cstdint>
#include <string>
#include <string_view>

#include "core/scene.h"

namespace patchsim {

struct SceneLimits {
    // Largest film the renderer may allocate, in bytes of per-sample state (about 32 bytes per
    // sample); checked before anything is allocated.
    std::uint64_t memoryBudgetBytes = std::uint64_t(4) << 30;
};

SceneDesc readSceneFile(const std::string& path, const SceneLimits& limits = {});
// `path` names the text in errors; relative cage paths resolve against `baseDir`.
SceneDesc parseScene(std::string_view text, const std::string& path, const std::string& baseDir,
                     const SceneLimits& limits = {});

// A scene around one cage (an .obj path given where a scene is expected): the cage at the
// origin, static, framed by a camera on +z, integer factor 4.
SceneDesc sceneForCage(const std::string& objPath, const SceneLimits& limits = {});

// A scene file, or a scene around a cage when `path` ends in ".obj".
SceneDesc readSceneOrCage(const std::string& path, const SceneLimits& limits = {});

// The built-in default scene (motion blur and defocus together), with built-in cages.
SceneDesc defaultScene(const SceneLimits& limits = {});

// Bytes a film of this size needs for per-sample state.
std::uint64_t filmBytes(const FilmDesc& film);

// Throws InputError(source, field, ...) when the film needs more than the budget. Every scene
// a command renders passes here, wherever its film came from (file, default, grid override).
void checkMemoryBudget(const FilmDesc& film, const SceneLimits& limits, const std::string& source,
                       const std::string& field = "film.spp");

}  // namespace patchsim
