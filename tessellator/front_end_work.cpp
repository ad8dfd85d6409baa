#include "tessellator/front_end_work.h"

namespace patchsim {

PATCHSIM_WORK_DEFINE(FrontEndWork, FrontEndCounters, frontEndCounters, PATCHSIM_FRONT_END_WORK)

}  // namespace patchsim
