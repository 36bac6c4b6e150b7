// The one source of bw_test_pch and bw_test_pch_computing (tests/CMakeLists.txt), which
// precompile support/test_pch.h for every test target: a target needs a C++ source to have one.
