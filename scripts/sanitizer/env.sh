# Sanitizer settings shared by scripts/test_sanitize.sh, fuzz.sh and soak.sh
# (source it; ROOT is the repository root).
#
# fast_unwind_on_malloc=0: record each allocation's stack with the slow
# unwinder instead of following frame pointers. Mesa is built without frame
# pointers, so the fast unwinder stops at the first Mesa frame; an
# allocation made inside the DRI driver (swrast_dri.so) is then known only by
# an address in a module that eglTerminate has unloaded by the time
# LeakSanitizer reports at exit ("<unknown module>"), and no suppression can
# name it. With full stacks the same allocation shows its callers,
# libEGL_mesa's eglInitialize and Ripple's EglContext::Init, and the
# libEGL_mesa suppression in lsan.supp matches it (docs/reliability.md,
# "Sanitizer build"). It costs about 15 % of the run time.
export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1:detect_stack_use_after_return=0:fast_unwind_on_malloc=0
export LSAN_OPTIONS=suppressions=$ROOT/scripts/sanitizer/lsan.supp:print_suppressions=0
export UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1
