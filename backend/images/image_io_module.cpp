#include "backend/images/image_io_module.h"

#include <dlfcn.h>

#include <cstdlib>
#include <exception>
#include <filesystem>
#include <mutex>
#include <system_error>
#include <thread>
#include <vector>

#include "core/error.h"

namespace patchsim {
namespace {

// The module's path in this build tree (set by backend/images/CMakeLists.txt).
constexpr const char* kBuildTreeModule = PATCHSIM_IMAGE_IO_MODULE;
constexpr const char* kModuleFile = "libpatchsim_image_io.so";
constexpr const char* kModuleVariable = "PATCHSIM_IMAGE_IO_MODULE";

bool isFile(const std::string& path) {
    std::error_code error;
    return std::filesystem::is_regular_file(path, error);
}

// Where the module is looked for, in order.
std::vector<std::string> moduleCandidates() {
    if (const char* chosen = std::getenv(kModuleVariable); chosen && *chosen) return {chosen};
    std::vector<std::string> candidates{kBuildTreeModule};
    std::error_code error;
    const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", error);
    if (!error) candidates.push_back((self.parent_path() / kModuleFile).string());
    return candidates;
}

struct ModuleLoad {
    std::once_flag once;
    const ImageIoTable* table = nullptr;
    std::exception_ptr failure;  // an InputError naming the module, when the load failed
    std::thread preload;
    // The process does not end while the side thread is inside dlopen.
    ~ModuleLoad() {
        if (preload.joinable()) preload.join();
    }
};

ModuleLoad& moduleLoad() {
    static ModuleLoad load;
    return load;
}

void loadModule(ModuleLoad& load) {
    std::string path;
    try {
        path = imageIoModulePath();
    } catch (const InputError&) {
        load.failure = std::current_exception();
        return;
    }
    void* handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!handle) {
        const char* why = dlerror();
        load.failure = std::make_exception_ptr(InputError(
            path, "", std::string("cannot load patchsim's image module: ") + (why ? why : "")));
        return;
    }
    using Entry = const ImageIoTable* (*)();
    const auto entry = reinterpret_cast<Entry>(dlsym(handle, "patchsim_image_io"));
    const ImageIoTable* table = entry ? entry() : nullptr;
    if (!table || table->version != kImageIoVersion) {
        load.failure = std::make_exception_ptr(
            InputError(path, "", "not patchsim's image module of this build (rebuild patchsim)"));
        return;
    }
    load.table = table;
}

}  // namespace

std::string imageIoModulePath() {
    const std::vector<std::string> candidates = moduleCandidates();
    for (const std::string& path : candidates)
        if (isFile(path)) return path;
    std::string looked;
    for (const std::string& path : candidates) looked += (looked.empty() ? "" : ", ") + path;
    throw InputError(candidates.front(), "",
                     "patchsim's image module (OpenImageIO) is missing; looked at " + looked +
                         ". Build patchsim (the build makes it), or set " +
                         std::string(kModuleVariable) + " to its path");
}

const ImageIoTable& imageIo() {
    ModuleLoad& load = moduleLoad();
    std::call_once(load.once, [&] { loadModule(load); });
    if (!load.table) std::rethrow_exception(load.failure);
    return *load.table;
}

void preloadImageIo() {
    imageIoModulePath();  // a missing module is refused now, not after the frame's work
    ModuleLoad& load = moduleLoad();
    if (load.preload.joinable()) return;
    load.preload = std::thread([&load] { std::call_once(load.once, [&] { loadModule(load); }); });
}

}  // namespace patchsim
