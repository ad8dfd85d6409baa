#include "core/stage_ops.h"

namespace patchsim {

namespace {

constexpr const char* kStageNames[kStageCount] = {"IA", "VS", "HS", "TS", "DS", "RS", "PS", "OM"};

struct OpInfo {
    const char* key;
    Stage stage;
    const char* definition;
};

constexpr OpInfo kOps[kOpCount] = {
#define PATCHSIM_OP_INFO(op, key, stage, definition) {key, Stage::stage, definition},
    PATCHSIM_STAGE_OPS(PATCHSIM_OP_INFO)
#undef PATCHSIM_OP_INFO
};

}  // namespace

const char* stageName(Stage s) {
    return kStageNames[int(s)];
}

const char* opName(Op op) {
    return kOps[int(op)].key;
}

const char* opDefinition(Op op) {
    return kOps[int(op)].definition;
}

Stage stageOf(Op op) {
    return kOps[int(op)].stage;
}

}  // namespace patchsim
