// Registers every backend this build has; the prism command, the tests and the bench programs link this.
#include "core/backend.h"

namespace prism {

void register_builtin_backends() {}

}  // namespace prism
