# Sanitizer settings shared by scripts/test_sanitize.sh, fuzz.sh and soak.sh
# (source it; ROOT is the repository root).
#
# Leak checking stays on with the fast (frame-pointer) unwinder. The one
# leak that used to end every EGL replay, an allocation inside Mesa's DRI
# driver reported after eglTerminate had unloaded it, is gone since the
# EGL backend keeps the driver loaded (render/context_egl.cc).
# fast_unwind_on_malloc=0 would attribute it too, but deadlocks when
# llvmpipe's JIT registers unwind tables (libgcc's unwinder mallocs under
# its own lock; docs/reliability.md, "Sanitizer build").
export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1:detect_stack_use_after_return=0
export LSAN_OPTIONS=suppressions=$ROOT/scripts/sanitizer/lsan.supp:print_suppressions=0
export UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1
