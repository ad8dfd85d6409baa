#pragma once
// The names of a small enum, as scene files and the command line spell them: one table per enum,
// read both ways, so a name is written once.

#include <cstddef>
#include <string>
#include <string_view>

namespace patchsim {

template <typename E>
struct EnumName {
    E value;
    const char* name;
};

template <typename E, std::size_t N>
const char* nameIn(const EnumName<E> (&names)[N], E value) {
    for (const EnumName<E>& n : names)
        if (n.value == value) return n.name;
    return "?";
}

template <typename E, std::size_t N>
bool parseIn(const EnumName<E> (&names)[N], std::string_view name, E& out) {
    for (const EnumName<E>& n : names) {
        if (name == n.name) {
            out = n.value;
            return true;
        }
    }
    return false;
}

// "a, b, c", for messages that list what is accepted.
template <typename E, std::size_t N>
std::string namesIn(const EnumName<E> (&names)[N]) {
    std::string list;
    for (const EnumName<E>& n : names) list += (list.empty() ? "" : ", ") + std::string(n.name);
    return list;
}

}  // namespace patchsim
