// The source of ripple_test_pch (tests/CMakeLists.txt): the target exists to
// build the precompiled header the test targets reuse; it defines nothing.
