// Fuzzes the hardware-configuration reader: any input either parses or throws InputError.

#include <cstddef>
#include <cstdint>
#include <string_view>

#include "core/error.h"
#include "pipeline/timing/hardware_config.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    try {
        patchsim::parseHardwareConfig(text, "fuzz.json");
    } catch (const patchsim::InputError&) {
    }
    return 0;
}
