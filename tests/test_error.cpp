#include "core/util/error.h"
#include <gtest/gtest.h>
TEST(Skeleton, ErrorCarriesMessage) { EXPECT_STREQ(prism::file_error("a.ply", 3, "bad").what(), "a.ply:3: bad"); }
