#include "pipeline/core/json_fields.h"

namespace patchsim {

namespace {

// Line and column (1-based) of a byte offset, for syntax errors.
std::string lineColumn(std::string_view text, std::size_t byte) {
    std::size_t line = 1, column = 1;
    for (std::size_t i = 0; i < std::min(byte, text.size()); ++i) {
        if (text[i] == '\n') {
            ++line;
            column = 1;
        } else {
            ++column;
        }
    }
    return "line " + std::to_string(line) + ", column " + std::to_string(column);
}

}  // namespace

Json parseJson(std::string_view text, const std::string& path) {
    try {
        return Json::parse(text.begin(), text.end());
    } catch (const Json::parse_error& e) {
        // nlohmann reports the byte just past the offending token.
        const std::size_t byte = e.byte > 0 ? e.byte - 1 : 0;
        std::string message = e.what();
        if (auto pos = message.find("syntax error"); pos != std::string::npos)
            message = message.substr(pos);
        throw InputError(path, lineColumn(text, byte), "JSON " + message);
    } catch (const Json::exception& e) {
        // Numbers beyond double range ("number overflow parsing '1e999'").
        std::string message = e.what();
        if (auto pos = message.find(']'); pos != std::string::npos)
            message = message.substr(pos + 2);
        throw InputError(path, "", "JSON " + message);
    }
}

}  // namespace patchsim
