#include "backend/images/image_io_module.h"

#include <dlfcn.h>

#include <mutex>
#include <thread>

#include "core/error.h"

namespace patchsim {
namespace {

// The module's path in this build tree (set by backend/images/CMakeLists.txt).
constexpr const char* kModulePath = PATCHSIM_IMAGE_IO_MODULE;

struct ModuleLoad {
    std::once_flag once;
    const ImageIoTable* table = nullptr;
    std::string error;
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
    void* handle = dlopen(kModulePath, RTLD_NOW | RTLD_LOCAL);
    if (!handle) {
        const char* why = dlerror();
        load.error = why ? why : "dlopen failed";
        return;
    }
    using Entry = const ImageIoTable* (*)();
    const auto entry = reinterpret_cast<Entry>(dlsym(handle, "patchsim_image_io"));
    const ImageIoTable* table = entry ? entry() : nullptr;
    if (!table || table->version != kImageIoVersion) {
        load.error = "not patchsim's image module of this build (rebuild patchsim)";
        return;
    }
    load.table = table;
}

}  // namespace

const ImageIoTable& imageIo() {
    ModuleLoad& load = moduleLoad();
    std::call_once(load.once, [&] { loadModule(load); });
    if (!load.table)
        throw InputError(kModulePath, "", "cannot load the image module: " + load.error);
    return *load.table;
}

void preloadImageIo() {
    ModuleLoad& load = moduleLoad();
    if (load.preload.joinable()) return;
    load.preload = std::thread([&load] { std::call_once(load.once, [&] { loadModule(load); }); });
}

}  // namespace patchsim
