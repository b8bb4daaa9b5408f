// Chapter 01: the smallest useful compute shader. Two arrays go to the GPU, one
// comes back holding a[i] + b[i] + constant, and the CPU checks every element.
#include <cmath>
#include <cstdio>
#include <vector>

#include "course/session.h"
#include "shared.h"  // buffer bindings and the work-group size, shared with GLSL

int main(int argc, char** argv) {
    course::CommandLine cli("Chapter 01: add two float buffers on the GPU and check them");
    int count = 1000;
    float constant = 0.5f;
    cli.withoutImage();  // this chapter checks numbers; there is no picture yet
    cli.option("--count", "N", "number of floats in each buffer", &count, 1, 64 << 20);
    return course::run(cli, argc, argv, [&](course::Session& session) {
        // --8<-- [start:inputs]
        // 1. Inputs on the CPU: values whose sums are exact in float, so the GPU's
        //    answer must match the CPU's bit for bit.
        std::vector<float> a(count), b(count);
        for (int i = 0; i < count; ++i) {
            a[i] = float(i % 1024) * 0.25f;
            b[i] = float(i % 7) - 3.0f;
        }
        // --8<-- [end:inputs]

        // --8<-- [start:upload]
        // 2. Copy them into storage buffers and bind each to the slot the shader's
        //    `layout(binding = N)` names.
        auto bufferA = course::GpuBuffer::fromVector(a);
        auto bufferB = course::GpuBuffer::fromVector(b);
        course::GpuBuffer bufferSum(count * sizeof(float));
        bufferA.bindStorage(INPUT_A_BINDING);
        bufferB.bindStorage(INPUT_B_BINDING);
        bufferSum.bindStorage(OUTPUT_BINDING);
        // --8<-- [end:upload]

        // --8<-- [start:dispatch]
        // 3. One invocation per element: ceil(count / WORKGROUP_SIZE) work groups.
        course::ShaderProgram& add = session.loadCompute("add.comp");
        add.set("count", unsigned(count));
        add.set("constant", constant);
        session.timeRender([&] { add.dispatchCovering(count); });
        // --8<-- [end:dispatch]

        // --8<-- [start:check]
        // 4. Read the sums back and compare with the CPU's.
        std::vector<float> sum = bufferSum.readAll<float>();
        int mismatches = 0;
        for (int i = 0; i < count; ++i) {
            float expected = a[i] + b[i] + constant;
            if (sum[i] != expected && mismatches++ < 5)
                std::fprintf(stderr, "sum[%d] = %g, expected %g\n", i, sum[i], expected);
        }
        // --8<-- [end:check]

        int groups = (count + WORKGROUP_SIZE - 1) / WORKGROUP_SIZE;
        session.stats().set("count", count);
        session.stats().set("work_groups", groups);
        session.stats().set("mismatches", mismatches);
        if (!session.options().json)
            std::printf("added %d floats in %d work groups of %d in %.3f ms: %s\n", count,
                        groups, WORKGROUP_SIZE, session.stats().number("gpu_ms"),
                        mismatches ? "MISMATCH" : "all correct");
        if (mismatches)
            course::fail(course::ExitCode::CheckFailed,
                         std::to_string(mismatches) + " of " + std::to_string(count) +
                             " sums are wrong");
    });
}
