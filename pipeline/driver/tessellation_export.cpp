#include "pipeline/driver/tessellation_export.h"

#include <array>
#include <bit>
#include <cstdio>
#include <map>

#include "core/parallel.h"

namespace patchsim {

namespace {

using WeldKey = std::array<std::uint32_t, 6>;

WeldKey weldKey(const Vec3& a, const Vec3& b) {
    return {std::bit_cast<std::uint32_t>(a.x), std::bit_cast<std::uint32_t>(a.y),
            std::bit_cast<std::uint32_t>(a.z), std::bit_cast<std::uint32_t>(b.x),
            std::bit_cast<std::uint32_t>(b.y), std::bit_cast<std::uint32_t>(b.z)};
}

void writeVec(std::ostream& out, const char* tag, const Vec3& v) {
    char line[96];
    std::snprintf(line, sizeof line, "%s %.7g %.7g %.7g\n", tag, double(v.x), double(v.y),
                  double(v.z));
    out << line;
}

}  // namespace

TessellationSummary writeTessellationObj(const FrontEnd& frontEnd, const TessellateOptions& options,
                                         std::ostream& out) {
    const std::size_t count = frontEnd.patchCount();
    std::vector<TessellatedPatch> patches(count);
    const int workers = resolveThreadCount(options.threads);
    std::vector<FrontEndWorkspace> workspaces;
    for (int w = 0; w < workers; ++w) workspaces.push_back(frontEnd.makeWorkspace());
    parallelFor(count, workers, [&](int worker, std::size_t i) {
        frontEnd.tessellate(i, patches[i], workspaces[std::size_t(worker)]);
    });

    TessellationSummary summary;
    summary.patches = count;
    const float t = options.time;
    out << "# patchsim tessellation of " << frontEnd.scene().path << " at shutter time " << t
        << "\n";
    std::map<WeldKey, std::size_t> welded;
    int currentObject = -1;
    for (const TessellatedPatch& p : patches) {
        if (p.object != currentObject) {
            currentObject = p.object;
            out << "o " << frontEnd.objects()[std::size_t(p.object)].desc.name << "\n";
        }
        std::vector<std::size_t> index(p.tessellation.points.size());
        for (std::size_t k = 0; k < index.size(); ++k) {
            const auto [it, inserted] =
                welded.emplace(weldKey(p.position[0][k], p.position[1][k]), welded.size() + 1);
            index[k] = it->second;
            if (!inserted) continue;
            writeVec(out, "v", lerp(p.position[0][k], p.position[1][k], t));
            const Vec3 n = lerp(p.normal[0][k], p.normal[1][k], t);
            const float len = glm::length(n);
            writeVec(out, "vn", len > 0 ? n / len : Vec3(0, 0, 1));
        }
        const auto& idx = p.tessellation.indices;
        for (std::size_t k = 0; k + 2 < idx.size(); k += 3) {
            out << "f " << index[idx[k]] << "//" << index[idx[k]] << " " << index[idx[k + 1]]
                << "//" << index[idx[k + 1]] << " " << index[idx[k + 2]] << "//"
                << index[idx[k + 2]] << "\n";
        }
        summary.triangles += p.triangleCount();
    }
    summary.vertices = welded.size();
    return summary;
}

}  // namespace patchsim
