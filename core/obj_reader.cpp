#include "core/obj_reader.h"

#include <charconv>
#include <cmath>
#include <limits>
#include <map>
#include <utility>

#include "core/error.h"
#include "core/text_file.h"

namespace patchsim {

namespace {

// A tag's values of one kind: far more than any crease or corner list, and small enough that the
// three counts add up without overflow.
constexpr int kMaxTagValues = 1 << 24;

// The scene reader's cap on every number (scene_reader.cpp, kHuge): a cage coordinate near the
// float limit (3e38) overflows to infinity once its object is scaled, and the limit points it
// touches become NaN, so it is refused here with its line and column.
constexpr float kMaxCoordinate = 1e30f;

struct Token {
    std::string_view text;
    int column;  // 1-based
};

std::vector<Token> tokenize(std::string_view line) {
    std::vector<Token> tokens;
    std::size_t i = 0;
    while (i < line.size()) {
        while (i < line.size() && (line[i] == ' ' || line[i] == '\t' || line[i] == '\r')) ++i;
        const std::size_t start = i;
        while (i < line.size() && line[i] != ' ' && line[i] != '\t' && line[i] != '\r') ++i;
        if (i > start) tokens.push_back({line.substr(start, i - start), int(start) + 1});
    }
    return tokens;
}

class ObjParser {
  public:
    ObjParser(std::string_view text, const std::string& path) : text_(text), path_(path) {}

    Cage parse() {
        std::size_t pos = 0;
        while (pos <= text_.size()) {
            std::size_t end = text_.find('\n', pos);
            if (end == std::string_view::npos) end = text_.size();
            ++line_;
            parseLine(text_.substr(pos, end - pos));
            pos = end + 1;
        }
        validate();
        return std::move(cage_);
    }

  private:
    [[noreturn]] void fail(int column, const std::string& message) const {
        throw InputError(
            path_, "line " + std::to_string(line_) + ", column " + std::to_string(column), message);
    }

    float number(const Token& t) const {
        float v = 0;
        const char* first = t.text.data();
        const char* last = first + t.text.size();
        if (*first == '+') ++first;
        auto [ptr, ec] = std::from_chars(first, last, v);
        if (ec != std::errc() || ptr != last)
            fail(t.column, "expected a number, found '" + std::string(t.text) + "'");
        if (!std::isfinite(v)) fail(t.column, "coordinate must be finite");
        return v;
    }

    float coordinate(const Token& t) const {
        const float v = number(t);
        if (std::abs(v) > kMaxCoordinate)
            fail(t.column, "coordinate " + std::string(t.text) + " is outside [-1e+30, 1e+30]");
        return v;
    }

    long integer(std::string_view text, int column) const {
        long v = 0;
        auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
        if (ec != std::errc() || ptr != text.data() + text.size())
            fail(column, "expected an integer, found '" + std::string(text) + "'");
        return v;
    }

    void parseLine(std::string_view line) {
        if (auto hash = line.find('#'); hash != std::string_view::npos) line = line.substr(0, hash);
        const std::vector<Token> tokens = tokenize(line);
        if (tokens.empty()) return;
        const std::string_view kind = tokens[0].text;
        if (kind == "v") {
            if (tokens.size() < 4) fail(tokens[0].column, "vertex needs 3 coordinates");
            cage_.positions.push_back(
                {coordinate(tokens[1]), coordinate(tokens[2]), coordinate(tokens[3])});
        } else if (kind == "f") {
            parseFace(tokens);
        } else if (kind == "t") {
            parseTag(tokens);
        } else if (kind == "vt" || kind == "vn" || kind == "vp" || kind == "g" || kind == "o" ||
                   kind == "s" || kind == "usemtl" || kind == "mtllib" || kind == "l" ||
                   kind == "p") {
            // Not part of the control cage's limit surface.
        } else {
            fail(tokens[0].column, "unknown OBJ statement '" + std::string(kind) + "'");
        }
    }

    void parseFace(const std::vector<Token>& tokens) {
        if (tokens.size() < 4) fail(tokens[0].column, "face needs at least 3 vertices");
        const int vertexCount = static_cast<int>(cage_.positions.size());
        for (std::size_t i = 1; i < tokens.size(); ++i) {
            const std::string_view ref = tokens[i].text.substr(0, tokens[i].text.find('/'));
            long index = integer(ref, tokens[i].column);
            if (index < 0) index = vertexCount + index + 1;  // relative reference
            if (index < 1 || index > vertexCount) {
                fail(tokens[i].column, "vertex index " + std::string(ref) + " out of range (" +
                                           std::to_string(vertexCount) + " vertices so far)");
            }
            cage_.faceVertices.push_back(static_cast<int>(index - 1));
        }
        cage_.faceSizes.push_back(static_cast<int>(tokens.size() - 1));
        faceLines_.push_back(line_);
    }

    struct TagCounts {
        int ints, floats, strings;
    };

    // "nint/nfloat/nstring", each a whole number from 0 to kMaxTagValues.
    TagCounts tagCounts(const Token& counts) const {
        const std::string_view text = counts.text;
        const std::size_t a = text.find('/'), b = text.find('/', a == text.npos ? a : a + 1);
        if (a == text.npos || b == text.npos || text.find('/', b + 1) != text.npos)
            fail(counts.column, "tag counts must be nint/nfloat/nstring");
        const std::string_view parts[3] = {text.substr(0, a), text.substr(a + 1, b - a - 1),
                                           text.substr(b + 1)};
        int values[3];
        for (int k = 0; k < 3; ++k) {
            const long v = integer(parts[k], counts.column);
            if (v < 0 || v > long(kMaxTagValues))
                fail(counts.column, "tag counts must be nint/nfloat/nstring, each 0 to " +
                                        std::to_string(kMaxTagValues));
            values[k] = int(v);
        }
        return {values[0], values[1], values[2]};
    }

    void parseTag(const std::vector<Token>& tokens) {
        if (tokens.size() < 3) fail(tokens[0].column, "tag needs a name and nint/nfloat/nstring");
        const std::string name(tokens[1].text);
        const Token& counts = tokens[2];
        const auto [nint, nfloat, nstring] = tagCounts(counts);
        if (tokens.size() != 3u + std::size_t(nint + nfloat + nstring))
            fail(counts.column, "tag '" + name + "' declares " +
                                    std::to_string(nint + nfloat + nstring) + " values but has " +
                                    std::to_string(tokens.size() - 3));
        std::vector<int> ints;
        std::vector<float> floats;
        std::vector<std::string> strings;
        std::vector<int> intColumns;
        for (int i = 0; i < nint; ++i) {
            const Token& t = tokens[3 + std::size_t(i)];
            const long value = integer(t.text, t.column);
            if (value < std::numeric_limits<int>::min() || value > std::numeric_limits<int>::max())
                fail(t.column, "tag value " + std::string(t.text) + " is out of range");
            ints.push_back(static_cast<int>(value));
            intColumns.push_back(t.column);
        }
        for (int i = 0; i < nfloat; ++i)
            floats.push_back(number(tokens[3 + std::size_t(nint + i)]));
        for (int i = 0; i < nstring; ++i)
            strings.emplace_back(tokens[3 + std::size_t(nint + nfloat + i)].text);
        applyTag(name, ints, intColumns, floats, strings, tokens[1].column);
    }

    void applyTag(const std::string& name, const std::vector<int>& ints,
                  const std::vector<int>& intColumns, const std::vector<float>& floats,
                  const std::vector<std::string>& strings, int column) {
        auto sharpnessAt = [&](std::size_t i) {
            const float s = floats.size() == 1 ? floats[0] : floats[i];
            if (s < 0) fail(column, "sharpness must not be negative");
            return s;
        };
        if (name == "crease") {
            if (ints.size() < 2 || (floats.size() != 1 && floats.size() != ints.size() - 1))
                fail(column, "crease needs a vertex chain and 1 or one-per-edge sharpness");
            for (std::size_t i = 0; i + 1 < ints.size(); ++i)
                cage_.creases.push_back({ints[i], ints[i + 1], sharpnessAt(i)});
            tagVertices_.push_back({ints, intColumns, line_});
        } else if (name == "corner") {
            if (ints.empty() || (floats.size() != 1 && floats.size() != ints.size()))
                fail(column, "corner needs vertices and 1 or one-per-vertex sharpness");
            for (std::size_t i = 0; i < ints.size(); ++i)
                cage_.corners.push_back({ints[i], sharpnessAt(i)});
            tagVertices_.push_back({ints, intColumns, line_});
        } else if (name == "hole") {
            for (std::size_t i = 0; i < ints.size(); ++i) cage_.holes.push_back(ints[i]);
            tagFaces_.push_back({ints, intColumns, line_});
        } else if (name == "interpolateboundary") {
            if (ints.size() != 1 || ints[0] < 0 || ints[0] > 2)
                fail(column, "interpolateboundary takes one integer 0, 1 or 2");
            // RenderMan's convention, as OpenSubdiv's shapes use it.
            static constexpr BoundaryInterpolation kModes[3] = {
                BoundaryInterpolation::None, BoundaryInterpolation::EdgeAndCorner,
                BoundaryInterpolation::EdgeOnly};
            cage_.boundary = kModes[ints[0]];
        } else if (name == "creasemethod") {
            if (strings.size() != 1 || (strings[0] != "chaikin" && strings[0] != "normal"))
                fail(column, "creasemethod takes one string: chaikin or normal");
            cage_.creaseMethod =
                strings[0] == "chaikin" ? CreaseMethod::Chaikin : CreaseMethod::Uniform;
        } else if (name == "smoothtriangles") {
            cage_.smoothTriangles = ints.empty() ? true : ints[0] != 0;
        } else if (name == "facevaryinginterpolateboundary" ||
                   name == "facevaryingpropagatecorners") {
            // Face-varying data is not used by the simulator.
        } else if (name == "vertexedit" || name == "edgeedit" || name == "faceedit") {
            cage_.warnings.push_back(path_ + ": line " + std::to_string(line_) +
                                     ": hierarchical edit '" + name + "' skipped");
        } else {
            fail(column, "unknown tag '" + name + "'");
        }
    }

    void validate() {
        if (cage_.positions.empty()) throw InputError(path_, "v", "the cage has no vertices");
        if (cage_.faceSizes.empty()) throw InputError(path_, "f", "the cage has no faces");
        for (const TagRefs& refs : tagVertices_) {
            line_ = refs.line;
            for (std::size_t i = 0; i < refs.indices.size(); ++i) {
                if (refs.indices[i] < 0 || refs.indices[i] >= cage_.vertexCount())
                    fail(refs.columns[i], "tag vertex index " + std::to_string(refs.indices[i]) +
                                              " out of range [0, " +
                                              std::to_string(cage_.vertexCount()) + ")");
            }
        }
        for (const TagRefs& refs : tagFaces_) {
            line_ = refs.line;
            for (std::size_t i = 0; i < refs.indices.size(); ++i) {
                if (refs.indices[i] < 0 || refs.indices[i] >= cage_.faceCount())
                    fail(refs.columns[i], "tag face index " + std::to_string(refs.indices[i]) +
                                              " out of range [0, " +
                                              std::to_string(cage_.faceCount()) + ")");
            }
        }
        validateTopology();
    }

    // A face that repeats a vertex has no surface. An edge used twice in the same direction (two
    // faces of opposite orientation, or more than two faces on an edge) is non-manifold:
    // OpenSubdiv accepts it (its regression shapes have such fans) and makes it sharp, so it is
    // reported as a warning, once per cage.
    void validateTopology() {
        std::map<std::pair<int, int>, int> directedEdges;
        bool warnedNonManifold = false, warnedDegenerate = false;
        std::size_t offset = 0;
        for (std::size_t f = 0; f < cage_.faceSizes.size(); ++f) {
            const int n = cage_.faceSizes[f];
            line_ = faceLines_[f];
            for (int i = 0; i < n; ++i) {
                const int a = cage_.faceVertices[offset + std::size_t(i)];
                const int b = cage_.faceVertices[offset + std::size_t((i + 1) % n)];
                if (a == b) {
                    if (!warnedDegenerate) {
                        warnedDegenerate = true;
                        cage_.warnings.push_back(
                            path_ + ": line " + std::to_string(line_) + ": face " +
                            std::to_string(f + 1) + " repeats vertex " + std::to_string(a + 1) +
                            " (a degenerate edge, evaluated as OpenSubdiv does)");
                    }
                    continue;
                }
                auto [it, inserted] = directedEdges.emplace(std::make_pair(a, b), int(f));
                if (!inserted && !warnedNonManifold) {
                    warnedNonManifold = true;
                    cage_.warnings.push_back(
                        path_ + ": line " + std::to_string(line_) + ": non-manifold edge " +
                        std::to_string(a + 1) + "-" + std::to_string(b + 1) + " (faces " +
                        std::to_string(it->second + 1) + " and " + std::to_string(f + 1) +
                        " use it in the same direction); OpenSubdiv treats it as sharp");
                }
            }
            offset += std::size_t(n);
        }
    }

    struct TagRefs {
        std::vector<int> indices;
        std::vector<int> columns;
        int line;
    };

    std::string_view text_;
    const std::string& path_;
    int line_ = 0;
    Cage cage_;
    std::vector<int> faceLines_;
    std::vector<TagRefs> tagVertices_;
    std::vector<TagRefs> tagFaces_;
};

}  // namespace

Cage parseObjCage(std::string_view text, const std::string& path) {
    return ObjParser(text, path).parse();
}

Cage readObjCage(const std::string& path, const std::string& referringFile,
                 const std::string& field) {
    return parseObjCage(readTextFile(path, referringFile, field), path);
}

}  // namespace patchsim
