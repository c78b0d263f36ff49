// The sanitizers' defaults in a SMOKESVD_SANITIZE build, linked into every program (smokesvd and the test
// programs); ASAN_OPTIONS, UBSAN_OPTIONS and LSAN_OPTIONS in the environment still override them.
//
// Undefined behaviour stops the program with a stack trace, as an address error does; a clean exit prints
// nothing (no table of the suppressions used on stderr, where tests read one-line errors). Leaks are reported,
// except those allocated inside libraries that are not the project's and keep memory to the end of the
// process by design (caches, registries, thread-local state): the Vulkan driver (lavapipe, the LLVM it
// compiles shaders with, its X11/xcb window-system libraries), the validation layer, OpenVDB, protobuf and
// ICU (loaded with OpenCV), and one block of the UndefinedBehaviorSanitizer's own runtime. Those libraries
// have no frame pointers, so the sanitizer's fast unwinder sees only the allocating frame: a suppression
// matches that library, never a project frame.
//
// The Vulkan loader unloads the driver and the layer at vkDestroyInstance; their allocations would then be
// reported from an "<unknown module>" no suppression can name. Opening both once more with RTLD_NODELETE
// keeps them mapped to the end.
#include <dlfcn.h>

#include <initializer_list>

namespace {

[[maybe_unused]] const bool kDriverAndLayerKept = [] {
  for (const char* library : {"libvulkan_lvp.so", "libVkLayer_khronos_validation.so"})
    dlopen(library, RTLD_LAZY | RTLD_NODELETE);  // absent (another driver): nothing to keep
  return true;
}();

}  // namespace

extern "C" const char* __asan_default_options() { return "detect_leaks=1:print_suppressions=0:strict_string_checks=1:check_initialization_order=1"; }

extern "C" const char* __ubsan_default_options() { return "print_stacktrace=1:halt_on_error=1"; }

extern "C" const char* __lsan_default_suppressions() {
  return "leak:libvulkan_lvp.so\n"
         "leak:libLLVM\n"
         "leak:libxcb\n"
         "leak:libXau.so\n"
         "leak:libXdmcp.so\n"
         "leak:libbsd.so\n"
         "leak:libmd.so\n"
         "leak:libVkLayer_khronos_validation.so\n"
         "leak:libopenvdb.so\n"
         "leak:libprotobuf.so\n"
         "leak:libicuuc.so\n"
         "leak:libubsan.so\n";
}
