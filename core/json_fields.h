#pragma once
// Strict reading of JSON input files (scenes, hardware configurations): every key must be known,
// every value of the right type and range, and every error names the file and the field
// ("objects[1].material.opacity") or the line and column of a syntax error.

#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <string>
#include <string_view>

#include "core/error.h"
#include "core/math.h"

namespace patchsim {

using Json = nlohmann::json;

// Parses JSON text; syntax errors become InputError(path, "line L, column C", ...).
Json parseJson(std::string_view text, const std::string& path);

inline std::string typeName(const Json& j) {
    return j.type_name();
}

// One JSON object being read: every key must be consumed, or finish() reports the unknown one.
class ObjectReader {
  public:
    ObjectReader(const Json& json, std::string field, const std::string& file)
        : json_(json), field_(std::move(field)), file_(file) {
        if (!json_.is_object()) fail(field_, "expected an object, found " + typeName(json_));
    }

    [[noreturn]] void fail(const std::string& field, const std::string& message) const {
        throw InputError(file_, field, message);
    }

    std::string fieldName(const std::string& key) const {
        return field_.empty() ? key : field_ + "." + key;
    }

    const Json* find(const std::string& key) {
        auto it = json_.find(key);
        if (it == json_.end()) return nullptr;
        used_.insert(key);
        return &*it;
    }

    double number(const std::string& key, double fallback, double lo, double hi) {
        const Json* j = find(key);
        if (!j) return fallback;
        return checkNumber(*j, fieldName(key), lo, hi);
    }

    double requiredNumber(const std::string& key, double lo, double hi) {
        if (!json_.contains(key)) fail(fieldName(key), "missing required number");
        return number(key, 0, lo, hi);
    }

    double checkNumber(const Json& j, const std::string& field, double lo, double hi) const {
        if (!j.is_number()) fail(field, "expected a number, found " + typeName(j));
        const double v = j.get<double>();
        if (!std::isfinite(v)) fail(field, "must be a finite number");
        if (v < lo || v > hi) {
            fail(field, "value " + formatNumber(v) + " is outside [" + formatNumber(lo) + ", " +
                            formatNumber(hi) + "]");
        }
        return v;
    }

    std::int64_t integer(const std::string& key, std::int64_t fallback, std::int64_t lo,
                         std::int64_t hi) {
        const Json* j = find(key);
        if (!j) return fallback;
        if (!j->is_number_integer())
            fail(fieldName(key), "expected an integer, found " + typeName(*j));
        const std::int64_t v =
            j->is_number_unsigned()
                ? static_cast<std::int64_t>(std::min<std::uint64_t>(
                      j->get<std::uint64_t>(), std::numeric_limits<std::int64_t>::max()))
                : j->get<std::int64_t>();
        if (v < lo || v > hi) {
            fail(fieldName(key), "value " + std::to_string(v) + " is outside [" +
                                     std::to_string(lo) + ", " + std::to_string(hi) + "]");
        }
        return v;
    }

    std::string string(const std::string& key, const std::string& fallback) {
        const Json* j = find(key);
        if (!j) return fallback;
        if (!j->is_string()) fail(fieldName(key), "expected a string, found " + typeName(*j));
        return j->get<std::string>();
    }

    std::string requiredString(const std::string& key) {
        if (!json_.contains(key)) fail(fieldName(key), "missing required string");
        return string(key, "");
    }

    Vec3 vec3(const std::string& key, Vec3 fallback, double lo = -1e30, double hi = 1e30) {
        const Json* j = find(key);
        if (!j) return fallback;
        const std::string field = fieldName(key);
        if (!j->is_array() || j->size() != 3)
            fail(field, "expected an array of 3 numbers, found " + typeName(*j));
        Vec3 v;
        for (int i = 0; i < 3; ++i)
            v[i] = static_cast<float>(checkNumber((*j)[static_cast<std::size_t>(i)],
                                                  field + "[" + std::to_string(i) + "]", lo, hi));
        return v;
    }

    std::optional<ObjectReader> object(const std::string& key) {
        const Json* j = find(key);
        if (!j) return std::nullopt;
        return ObjectReader(*j, fieldName(key), file_);
    }

    void finish() const {
        for (auto it = json_.begin(); it != json_.end(); ++it) {
            if (!used_.count(it.key())) fail(fieldName(it.key()), "unknown key");
        }
    }

    const std::string& file() const { return file_; }

    static std::string formatNumber(double v) {
        char buffer[32];
        std::snprintf(buffer, sizeof buffer, "%g", v);
        return buffer;
    }

  private:
    const Json& json_;
    std::string field_;
    const std::string& file_;
    std::set<std::string> used_;
};

}  // namespace patchsim
