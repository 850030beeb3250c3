// The third-party and standard headers most tests read, precompiled once for all of them
// (tests/CMakeLists.txt): parsing gtest, nlohmann::json, Asio and the standard library took
// about 12 s of every test file's compile, most of the build. Only headers from outside the
// repository belong here, so that editing the project's own headers rebuilds no more than before.
#pragma once

#include <gtest/gtest.h>

#include <asio.hpp>
#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <random>
#include <regex>
#include <span>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

// Not third-party, but changed almost never: the functions behind SWEEPD_SHARED_DATA and friends.
#include "tests/test_paths.h"
