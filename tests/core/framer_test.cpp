#include <gtest/gtest.h>

#include "rangekit/core/framer.hpp"

TEST(Framer, Placeholder) { SUCCEED(); }
