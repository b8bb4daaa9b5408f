// The shared command line: defaults, every option, chapter options, bad usage.
#include <gtest/gtest.h>

#include <vector>

#include <glm/glm.hpp>

#include "course/cli.h"
#include "course/error.h"

using course::ExitCode;

namespace {

course::Options parse(course::CommandLine& cli, std::vector<const char*> args) {
    args.insert(args.begin(), "program");
    course::Options options;
    EXPECT_TRUE(cli.parse(int(args.size()), args.data(), options));
    return options;
}

std::string usageError(course::CommandLine& cli, std::vector<const char*> args) {
    args.insert(args.begin(), "program");
    course::Options options;
    try {
        cli.parse(int(args.size()), args.data(), options);
    } catch (const course::Failure& failure) {
        EXPECT_EQ(failure.code(), ExitCode::BadUsage);
        return failure.what();
    }
    ADD_FAILURE() << "accepted";
    return "";
}

}  // namespace

TEST(CommandLine, SharedOptions) {
    course::CommandLine cli("test");
    course::Options o = parse(cli, {"--headless", "--out", "a.pfm", "--width", "7", "--height",
                                    "9", "--spp", "16", "--seed", "42", "--backend", "osmesa",
                                    "--json", "--verbose"});
    EXPECT_FALSE(o.window);
    EXPECT_EQ(o.outPath, "a.pfm");
    EXPECT_EQ(o.width, 7);
    EXPECT_EQ(o.height, 9);
    EXPECT_EQ(o.spp, 16);
    EXPECT_EQ(o.seed, 42u);
    EXPECT_EQ(o.backend, course::Backend::OsMesa);
    EXPECT_TRUE(o.json);
    EXPECT_TRUE(o.verbose);
}

TEST(CommandLine, ChapterOptions) {
    course::CommandLine cli("test");
    bool direct = false;
    int depth = 5;
    std::string dispatch = "1d";
    cli.flag("--direct", "direct light only", &direct);
    cli.option("--depth", "N", "bounces", &depth, 1, 64);
    cli.choice("--dispatch", "shape", {"1d", "2d"}, &dispatch);
    parse(cli, {"--headless", "--direct", "--depth", "8", "--dispatch", "2d"});
    EXPECT_TRUE(direct);
    EXPECT_EQ(depth, 8);
    EXPECT_EQ(dispatch, "2d");
    EXPECT_NE(usageError(cli, {"--depth", "65"}).find("--depth must be between 1 and 64"),
              std::string::npos);
    EXPECT_NE(usageError(cli, {"--dispatch", "3d"}).find("one of 1d|2d"), std::string::npos);
    EXPECT_NE(cli.usage().find("--direct"), std::string::npos);
}

// The camera options of chapters 03-06: numbers and x,y,z vectors, typed and checked
// by the command line, their defaults in --help.
TEST(CommandLine, NumberAndVectorOptions) {
    course::CommandLine cli("test");
    float focal = 0.035f;
    glm::vec3 eye(0.0f, 1.0f, 4.0f), look(0.0f, -0.25f, -1.0f);
    cli.option("--focal", "M", "metres", &focal);
    cli.option("--eye", "X,Y,Z", "where", &eye);
    cli.option("--look", "X,Y,Z", "which way", &look);
    const std::string usage = cli.usage();
    EXPECT_NE(usage.find("--focal M               metres (default 0.035)"), std::string::npos)
        << usage;
    EXPECT_NE(usage.find("where (default 0,1,4)"), std::string::npos) << usage;
    EXPECT_NE(usage.find("which way (default 0,-0.25,-1)"), std::string::npos) << usage;

    parse(cli, {"--headless", "--focal", "1e-3", "--eye", "-1,0.5,2"});
    EXPECT_EQ(focal, 1e-3f);
    EXPECT_EQ(eye, glm::vec3(-1.0f, 0.5f, 2.0f));
    EXPECT_EQ(look, glm::vec3(0.0f, -0.25f, -1.0f));  // not given: the default stays

    EXPECT_EQ(usageError(cli, {"--eye", "1,2"}),
              "--eye expects three numbers x,y,z, got '1,2' (see --help)");
    EXPECT_EQ(usageError(cli, {"--eye", "1,2,3,4"}),
              "--eye expects three numbers x,y,z, got '1,2,3,4' (see --help)");
    EXPECT_EQ(usageError(cli, {"--eye", "1,,3"}),
              "--eye expects a finite number, got '' (see --help)");
    EXPECT_EQ(usageError(cli, {"--eye", "nan,0,0"}),
              "--eye expects a finite number, got 'nan' (see --help)");
    EXPECT_EQ(usageError(cli, {"--focal", "inf"}),
              "--focal expects a finite number, got 'inf' (see --help)");
    EXPECT_EQ(usageError(cli, {"--focal", "1e39"}),  // beyond float: infinity
              "--focal expects a finite number, got '1e39' (see --help)");
    EXPECT_EQ(usageError(cli, {"--focal", "0.5m"}),
              "--focal expects a finite number, got '0.5m' (see --help)");
    EXPECT_NE(usageError(cli, {"--look"}).find("--look needs a value"), std::string::npos);
}

TEST(CommandLine, BadUsage) {
    course::CommandLine cli("test");
    EXPECT_NE(usageError(cli, {"--width", "0"}).find("between 1 and"), std::string::npos);
    EXPECT_NE(usageError(cli, {"--width", "12x"}).find("whole number"), std::string::npos);
    EXPECT_NE(usageError(cli, {"--width", "99999999999999999999"}).find("whole number"),
              std::string::npos);
    EXPECT_NE(usageError(cli, {"--spp"}).find("needs a value"), std::string::npos);
    EXPECT_NE(usageError(cli, {"--obj", "x.obj"}).find("unknown option"), std::string::npos);
    EXPECT_NE(usageError(cli, {"--window", "--backend", "egl"}).find("glfw"), std::string::npos);
}

TEST(CommandLine, ObjOnlyWhereAccepted) {
    course::CommandLine cli("test");
    cli.acceptObj();
    EXPECT_EQ(parse(cli, {"--headless", "--obj", "teapot.obj"}).objPath, "teapot.obj");
}

TEST(CommandLine, HelpReturnsFalse) {
    course::CommandLine cli("test");
    const char* args[] = {"program", "--help"};
    course::Options options;
    EXPECT_FALSE(cli.parse(2, args, options));
}
