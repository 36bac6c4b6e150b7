// The command line's progress rate (cli/output.h): a rate only once there is one to show.
#include "cli/output.h"

#include <gtest/gtest.h>

// `estimate` printed "0 paths/s" for its first updates: before any path is done, or within the
// first tenth of a second, there is no rate yet.
TEST(PathRate, NoRateBeforeOneIsMeasured) {
    EXPECT_EQ(app::pathRate(0, 0.0), "-- paths/s");
    EXPECT_EQ(app::pathRate(0, 5.0), "-- paths/s");
    EXPECT_EQ(app::pathRate(16384, 0.05), "-- paths/s");
    EXPECT_EQ(app::pathRate(16384, 2.0), "8192 paths/s");
    EXPECT_EQ(app::pathRate(3, 0.1), "30 paths/s");
}
