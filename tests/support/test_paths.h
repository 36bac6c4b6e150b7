// Where the tests find the source tree (materials, shaders, captures, test data) and the
// workbench executable: $BW_TEST_SOURCE_ROOT and $BW_TEST_EXE when set, else this build's paths.
// The GPU test bundle (./run gpu-bundle, tests/bundle/) sets them, so its tests run from any
// folder on a machine without the source tree. Included into every test through the
// precompiled header (support/test_pch.h), where BW_SOURCE_ROOT and BW_EXE name these
// functions; test_paths.cpp defines them with this build's paths (BW_SOURCE_ROOT_BUILT, and
// BW_EXE_BUILT in the tests that run the executable), so this header depends on no macro.
#pragma once

namespace bwtest {

// $variable when set and not empty, else `built`.
const char* pathFromEnvironment(const char* variable, const char* built);
const char* sourceRoot();
const char* exe(); // only in the tests built with BW_EXE_BUILT

} // namespace bwtest
