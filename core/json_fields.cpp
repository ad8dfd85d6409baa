#include "core/json_fields.h"

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
        // Numbers beyond double range ("number overflow parsing '1e999'").
        std::string message = e.what();
        if (auto pos = message.find(']'); pos != std::string::npos)
            message = message.substr(pos + 2);
        throw InputError(path, "", "JSON " + message);
    }
}

}  // namespace patchsim
