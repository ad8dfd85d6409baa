#include "core/json_fields.h"

#include <cmath>
#include <cstdlib>

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

// Where the first number of `text` beyond double range begins, skipping strings; npos if none.
// nlohmann's out_of_range error 406 carries no position, but it is thrown at the first such
// number in the text (the parser reads in order, and a syntax error before it would have been
// reported instead), so the first one found here is the one it refused.
std::size_t firstOverflowingNumber(std::string_view text) {
    std::size_t i = 0;
    while (i < text.size()) {
        const char ch = text[i];
        if (ch == '"') {  // a string: skip to its closing quote, past escaped characters
            for (++i; i < text.size() && text[i] != '"'; ++i)
                if (text[i] == '\\') ++i;
            ++i;
        } else if (ch == '-' || (ch >= '0' && ch <= '9')) {
            const std::size_t start = i;
            while (i < text.size() &&
                   (text[i] == '-' || text[i] == '+' || text[i] == '.' || text[i] == 'e' ||
                    text[i] == 'E' || (text[i] >= '0' && text[i] <= '9')))
                ++i;
            // strtod is what nlohmann's lexer reads numbers with (the program keeps the "C"
            // locale), so it overflows on exactly the literals nlohmann refuses; an underflow
            // gives a finite 0 there and here.
            const std::string literal(text.substr(start, i - start));
            if (!std::isfinite(std::strtod(literal.c_str(), nullptr))) return start;
        } else {
            ++i;
        }
    }
    return std::string_view::npos;
}

}  // namespace

namespace {

// Keys seen so far in each open object, and the field path to it, to refuse a key given twice
// (nlohmann would silently keep the last).
class DuplicateKeyCheck {
  public:
    explicit DuplicateKeyCheck(const std::string& path) : path_(path) {}

    bool operator()(int, Json::parse_event_t event, Json& parsed) {
        switch (event) {
            case Json::parse_event_t::object_start:
                frames_.push_back({fieldOfValue(), {}, false});
                break;
            case Json::parse_event_t::array_start:
                frames_.push_back({fieldOfValue() + "[]", {}, true});
                break;
            case Json::parse_event_t::object_end:
            case Json::parse_event_t::array_end:
                frames_.pop_back();
                break;
            case Json::parse_event_t::key: {
                Frame& f = frames_.back();
                const std::string key = parsed.get<std::string>();
                if (!f.keys.insert(key).second)
                    throw InputError(path_, f.field.empty() ? key : f.field + "." + key,
                                     "key given twice");
                lastKey_ = key;
                break;
            }
            case Json::parse_event_t::value:
                break;
        }
        return true;
    }

  private:
    struct Frame {
        std::string field;
        std::set<std::string> keys;
        bool array;
    };
    // The field a value that starts now belongs to.
    std::string fieldOfValue() const {
        if (frames_.empty()) return "";
        const Frame& f = frames_.back();
        if (f.array) return f.field;
        return f.field.empty() ? lastKey_ : f.field + "." + lastKey_;
    }

    const std::string& path_;
    std::vector<Frame> frames_;
    std::string lastKey_;
};

}  // namespace

Json parseJson(std::string_view text, const std::string& path) {
    try {
        return Json::parse(text.begin(), text.end(), DuplicateKeyCheck(path));
    } catch (const Json::parse_error& e) {
        // nlohmann reports the byte just past the offending token.
        const std::size_t byte = e.byte > 0 ? e.byte - 1 : 0;
        std::string message = e.what();
        if (auto pos = message.find("syntax error"); pos != std::string::npos)
            message = message.substr(pos);
        throw InputError(path, lineColumn(text, byte), "JSON " + message);
    } catch (const Json::exception& e) {
        // Numbers beyond double range ("number overflow parsing '1e999'"), at the line and column
        // of the number (docs/SCENES.md: every error names a field or a position).
        std::string message = e.what();
        if (auto pos = message.find(']'); pos != std::string::npos)
            message = message.substr(pos + 2);
        const std::size_t number = firstOverflowingNumber(text);
        throw InputError(path, number == std::string_view::npos ? "" : lineColumn(text, number),
                         "JSON " + message);
    }
}

}  // namespace patchsim
