// Fuzzes the scene JSON reader: any input either parses or throws InputError; nothing else.

#include <cstddef>
#include <cstdint>
#include <string_view>

#include "core/error.h"
#include "core/scene_reader.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    try {
        patchsim::parseScene(text, "fuzz.json", "");
    } catch (const patchsim::InputError&) {
        // Rejected with a message: the expected outcome for most inputs.
    }
    return 0;
}
