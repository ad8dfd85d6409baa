// Fuzzes the OBJ cage reader: any input either parses or throws InputError; nothing else.

#include <cstddef>
#include <cstdint>
#include <string_view>

#include "core/error.h"
#include "core/obj_reader.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    try {
        patchsim::parseObjCage(text, "fuzz.obj");
    } catch (const patchsim::InputError&) {
    }
    return 0;
}
