// Linked into the widget tests of sanitized builds only. Mesa unloads its
// driver at exit, after which LeakSanitizer cannot name the module of the
// driver's own allocations, so lsan.supp cannot match them. Loading the
// driver first with RTLD_NODELETE keeps it mapped. Xvfb renders with
// swrast_dri.so (llvmpipe).
#include <dlfcn.h>

namespace {

[[maybe_unused]] const void* const kKeptDriver =
    dlopen("/usr/lib/x86_64-linux-gnu/dri/swrast_dri.so", RTLD_LAZY | RTLD_NODELETE);

}  // namespace
