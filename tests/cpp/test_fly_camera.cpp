// The fly-through camera's math (common/course/fly_camera.h), without a window.
#include <cmath>

#include <gtest/gtest.h>

#include "course/fly_camera.h"

namespace {

void expectNear(glm::vec3 a, glm::vec3 b) {
    EXPECT_NEAR(a.x, b.x, 1e-5f);
    EXPECT_NEAR(a.y, b.y, 1e-5f);
    EXPECT_NEAR(a.z, b.z, 1e-5f);
}

TEST(FlyCamera, LookingRecoversTheDirection) {
    for (glm::vec3 look :
         {glm::vec3(0, 0, -1), glm::vec3(1, 0, 0), glm::vec3(0.3f, -0.4f, 2)}) {
        auto camera = course::FlyCamera::looking({0, 0, 3.9f}, look, 1.0f);
        expectNear(camera.forward(), glm::normalize(look));
        EXPECT_NEAR(glm::dot(camera.right(), camera.forward()), 0.0f, 1e-6f);
        EXPECT_NEAR(camera.right().y, 0.0f, 1e-6f);  // the horizon stays level
    }
}

TEST(FlyCamera, WMovesForwardBySpeedTimesSeconds) {
    auto camera = course::FlyCamera::looking({0, 0, 3.9f}, {0, 0, -1}, 2.0f);
    EXPECT_FALSE(camera.update({}));  // no input: nothing changes, no restart
    EXPECT_TRUE(camera.update({{0, 0, 1}, {0, 0}, 0.5f}));
    expectNear(camera.eye, {0, 0, 2.9f});
    EXPECT_TRUE(camera.update({{1, 0, 0}, {0, 0}, 0.5f}));  // D: to the right, +x here
    expectNear(camera.eye, {1, 0, 2.9f});
}

TEST(FlyCamera, DraggingRightTurnsRightAndPitchStopsShortOfStraightUp) {
    auto camera = course::FlyCamera::looking({0, 0, 0}, {0, 0, -1}, 1.0f);
    camera.update({{0, 0, 0}, {100, 0}, 0.0f});
    EXPECT_GT(camera.forward().x, 0.0f);  // looking along -z, right is +x
    camera.update({{0, 0, 0}, {0, -1e6f}, 0.0f});  // drag far up
    EXPECT_NEAR(camera.pitch, glm::radians(89.0f), 1e-5f);
}

}  // namespace
