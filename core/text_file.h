#pragma once
// Reading whole input files, including the assets built into the binary ("builtin:NAME"). Output
// files are written through OutputSet (output_set.h).

#include <optional>
#include <string>
#include <string_view>

namespace patchsim {

// Throws InputError(path, field, ...) when the file cannot be read. `field` names what referred
// to the file (e.g. "objects[0].cage") so the message says where the path came from.
std::string readTextFile(const std::string& path, const std::string& referringFile = {},
                         const std::string& field = {});

// The built-in asset of that name ("default.json", "catmark_torus.obj", ...), if any.
std::optional<std::string_view> builtinAsset(std::string_view name);
inline constexpr std::string_view kBuiltinPrefix = "builtin:";

std::string parentDirectory(const std::string& path);
std::string joinPath(const std::string& dir, const std::string& relative);

}  // namespace patchsim
