// Option values the commands parse themselves (host/app/cli_options.h).
#include "app/cli_options.h"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

namespace whitted::test {
namespace {

std::string regionError(const std::string& text) {
    try {
        parsePixelRegion(text);
    } catch (const std::invalid_argument& e) {
        return e.what();
    }
    return "(accepted)";
}

TEST(CliOptions, RegionReadsFourIntegers) {
    EXPECT_EQ(parsePixelRegion("20,10,61,50"), (PixelRegion{20, 10, 61, 50}));
    EXPECT_EQ(parsePixelRegion("0,0,16384,16384"), (PixelRegion{0, 0, 16384, 16384}));
}

// Negative numbers are integers: the parser takes them, and the renderer,
// which knows the image, refuses a region outside it (Cli.BadRegionIsRefused).
TEST(CliOptions, RegionTakesNegativeNumbers) {
    EXPECT_EQ(parsePixelRegion("-4,-1,3,2"), (PixelRegion{-4, -1, 3, 2}));
}

TEST(CliOptions, RegionRefusesMissingFields) {
    EXPECT_EQ(regionError("1,2,3"), "expected X0,Y0,X1,Y1 (four integers), got '1,2,3'");
    EXPECT_EQ(regionError("1,2,,4"), "expected X0,Y0,X1,Y1 (four integers), got '1,2,,4'");
    EXPECT_EQ(regionError(",1,2,3"), "expected X0,Y0,X1,Y1 (four integers), got ',1,2,3'");
    EXPECT_EQ(regionError("1,2,3,"), "expected X0,Y0,X1,Y1 (four integers), got '1,2,3,'");
    EXPECT_EQ(regionError(""), "expected X0,Y0,X1,Y1 (four integers), got ''");
}

TEST(CliOptions, RegionRefusesTrailingJunk) {
    EXPECT_EQ(regionError("1,2,3,4x"), "expected X0,Y0,X1,Y1 (four integers), got '1,2,3,4x'");
    EXPECT_EQ(regionError("1,2,3,4,5"), "expected X0,Y0,X1,Y1 (four integers), got '1,2,3,4,5'");
    EXPECT_EQ(regionError("1,2,3,4.5"), "expected X0,Y0,X1,Y1 (four integers), got '1,2,3,4.5'");
    EXPECT_EQ(regionError("1,2,3,4 "), "expected X0,Y0,X1,Y1 (four integers), got '1,2,3,4 '");
}

TEST(CliOptions, RegionRefusesWhatIsNoInteger) {
    EXPECT_EQ(regionError("a,2,3,4"), "expected X0,Y0,X1,Y1 (four integers), got 'a,2,3,4'");
    EXPECT_EQ(regionError("1;2;3;4"), "expected X0,Y0,X1,Y1 (four integers), got '1;2;3;4'");
    EXPECT_EQ(regionError("0,0,99999999999,4"), "expected X0,Y0,X1,Y1 (four integers), got '0,0,99999999999,4'");
}

}  // namespace
}  // namespace whitted::test
