// The headers every test target shares, precompiled once per build tree (bw_test_pch,
// tests/CMakeLists.txt) and force-included into every test source: the test paths, GoogleTest,
// the standard library headers the tests use most, GLM and nlohmann/json. Parsing these took a
// large part of each test batch's compile time, once per batch.
#pragma once

#include "test_paths.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <numbers>
#include <optional>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>
