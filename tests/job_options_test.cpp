// The options table's rules (pipeline/app/job_options.h): one check per kind of value, applied to
// every row, and docs/OPTIONS.md generated from the table.

#include "pipeline/app/job_options.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <set>

#include "core/error.h"
#include "tests/test_paths.h"

namespace patchsim {
namespace {

// The error `text` gets from `option`, or "" when it is accepted.
std::string refusal(const JobOption& option, const std::string& text) {
    JobSettings s = defaultJobSettings(Command::Render);
    try {
        applyJobOption(option, text, s);
    } catch (const InputError& e) {
        EXPECT_EQ(e.file(), "command line");
        EXPECT_EQ(e.field(), option.longName());
        return e.what();
    }
    return {};
}

std::string numberText(double v) {
    char text[40];
    std::snprintf(text, sizeof text, "%.17g", v);
    return text;
}

// A sweep axis belongs to the methods whose parameter it is: a rasterizer option to every method
// that renders through the patch rasterizer, and only to them.
TEST(JobOptions, SweepAxesBelongToTheMethodsTheyChange) {
    const SweepAxis leaf = parseSweepAxis("leaf-size=2,4");
    EXPECT_EQ(leaf.methods,
              (std::vector<std::string>{"patch", "postprocess", "hybrid", "reprojection"}));
    EXPECT_EQ(leaf.values, (std::vector<std::string>{"2", "4"}));
    const SweepAxis tile = parseSweepAxis("pp-tile-size=10,20");
    EXPECT_EQ(tile.methods, (std::vector<std::string>{"postprocess", "hybrid"}));
    EXPECT_EQ(parseSweepAxis("time-strata=0,4").methods, std::vector<std::string>{"interval"});
    // One value written two ways is one run, not two.
    EXPECT_THROW(parseSweepAxis("time-strata=4,04"), InputError);
    EXPECT_THROW(parseSweepAxis("soft-z-extent=0.05,0.050"), InputError);
}

TEST(JobOptions, EveryNumberIsFiniteAndInRange) {
    int reals = 0;
    for (const JobOption& o : jobOptions()) {
        const bool numeric = o.kind == ValueKind::Real || o.kind == ValueKind::Integer ||
                             o.kind == ValueKind::RealList || o.kind == ValueKind::IntegerList;
        if (!numeric) continue;
        for (const char* bad : {"nan", "-nan", "NaN", "inf", "-inf", "infinity", "", "1e999", " 4",
                                "4 ", "0x10", "four"})
            EXPECT_NE(refusal(o, bad), "") << o.flag << " took '" << bad << "'";
        EXPECT_NE(refusal(o, numberText(o.hi * 2 + 1)), "") << o.flag;
        EXPECT_NE(refusal(o, numberText(o.lo - 1)), "") << o.flag;
        reals += o.kind == ValueKind::Real;
    }
    EXPECT_GE(reals, 3);  // --soft-z-extent, --edge-threshold, --time
}

TEST(JobOptions, RangesHonourTheirOpenEnds) {
    for (const JobOption& o : jobOptions()) {
        if (std::string(o.flag) == "--edge-threshold") {
            EXPECT_EQ(refusal(o, "0"), "");
            EXPECT_EQ(refusal(o, "0.999"), "");
            EXPECT_NE(refusal(o, "1"), "");
        }
        if (std::string(o.flag) == "--blur") {
            EXPECT_NE(refusal(o, "0"), "");
            // Above 0 as written, 0 as the float it is held in.
            EXPECT_NE(refusal(o, "1e-50").find("as a single-precision number"), std::string::npos);
            EXPECT_EQ(refusal(o, "1000"), "");
        }
        if (std::string(o.flag) == "--pp-samples") {
            EXPECT_EQ(refusal(o, "5"), "");
            EXPECT_NE(refusal(o, "4").find("4 is even; it must be odd"), std::string::npos);
        }
    }
}

TEST(JobOptions, ListsHaveNoEmptyOrRepeatedItems) {
    int lists = 0;
    for (const JobOption& o : jobOptions()) {
        const bool list = o.kind == ValueKind::IntegerList || o.kind == ValueKind::RealList ||
                          o.kind == ValueKind::NameList;
        if (!list) continue;
        ++lists;
        const std::string good = o.kind == ValueKind::NameList ? "patch" : "1";
        const std::string other = o.kind == ValueKind::NameList ? "interval" : "2";
        EXPECT_EQ(refusal(o, good + "," + other), "") << o.flag;
        for (const std::string& bad : {good + ",," + other, good + "," + other + ",", "," + good,
                                       std::string(","), std::string(), good + "," + good})
            EXPECT_NE(refusal(o, bad), "") << o.flag << " took '" << bad << "'";
        EXPECT_NE(refusal(o, good + ",," + other).find("empty item"), std::string::npos);
    }
    EXPECT_EQ(lists, 3);  // sweep's --methods, --spp, --blur
}

TEST(JobOptions, NoPathIsEmpty) {
    int paths = 0;
    for (const JobOption& o : jobOptions()) {
        const bool path = o.kind == ValueKind::InputPath || o.kind == ValueKind::OutputFile ||
                          o.kind == ValueKind::OutputFolder || o.kind == ValueKind::Text;
        if (!path) continue;
        ++paths;
        EXPECT_NE(refusal(o, "").find("empty"), std::string::npos) << o.flag;
        EXPECT_EQ(refusal(o, "x"), "") << o.flag;
    }
    EXPECT_GE(paths, 14);
}

TEST(JobOptions, NamesComeFromTheirLists) {
    for (const JobOption& o : jobOptions()) {
        if (o.kind != ValueKind::Name) continue;
        ASSERT_FALSE(o.choices.empty()) << o.flag;
        EXPECT_EQ(refusal(o, o.choices.back()), "") << o.flag;
        EXPECT_NE(refusal(o, "no-such-choice").find("is not one of"), std::string::npos);
    }
}

// Every command's rows: one flag each, and stats keys that name one option each.
TEST(JobOptions, EachCommandHasEachFlagAndStatsKeyOnce) {
    for (int c = 0; c < kCommandCount; ++c) {
        std::set<std::string> flags, keys;
        for (const JobOption& o : jobOptions()) {
            if (!o.takes(Command(c))) continue;
            EXPECT_TRUE(flags.insert(o.flag).second) << commandName(Command(c)) << " " << o.flag;
            if (o.statsKey) {
                EXPECT_TRUE(keys.insert(o.statsKey).second) << o.statsKey;
            }
            EXPECT_GT(std::string(o.help).size(), 10u) << o.flag;
        }
    }
}

TEST(JobOptions, DocsPageIsGeneratedFromTheTable) {
    std::ifstream in(test::sourcePath("docs/OPTIONS.md"));
    const std::string page((std::istreambuf_iterator<char>(in)), {});
    EXPECT_EQ(page, jobOptionsMarkdown())
        << "docs/OPTIONS.md is stale: build/pipeline/app/patchsim options > docs/OPTIONS.md";
}

}  // namespace
}  // namespace patchsim
