#include "rasterizer/verifier/tile_test_variant.h"

#include "core/enum_names.h"

namespace patchsim {

// ---- Registry ----

namespace {

std::vector<std::unique_ptr<TileTestVariant>>& tileTestRegistry() {
    static std::vector<std::unique_ptr<TileTestVariant>> registry = [] {
        std::vector<std::unique_ptr<TileTestVariant>> builtIn;
        addPatentTileTests(builtIn);
        addLiteratureTileTests(builtIn);
        return builtIn;
    }();
    return registry;
}

}  // namespace

void registerTileTest(std::unique_ptr<TileTestVariant> variant) {
    tileTestRegistry().push_back(std::move(variant));
}

void unregisterTileTest(const std::string& name) {
    std::erase_if(tileTestRegistry(), [&](const auto& v) { return v->name() == name; });
}

const std::vector<std::unique_ptr<TileTestVariant>>& registeredTileTests() {
    return tileTestRegistry();
}

namespace {

constexpr EnumName<CaseModel> kCaseModels[] = {{CaseModel::Pinhole, "pinhole"},
                                               {CaseModel::Lens, "lens"},
                                               {CaseModel::Hierarchy, "hierarchy"}};

}  // namespace

const char* caseModelName(CaseModel model) {
    return nameIn(kCaseModels, model);
}

bool parseCaseModel(const std::string& name, CaseModel& out) {
    return parseIn(kCaseModels, name, out);
}

}  // namespace patchsim
