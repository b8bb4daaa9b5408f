// What this GL allows a program, asked at run time rather than assumed. OpenGL 4.3
// guarantees little (8 storage blocks in a compute shader, 12 uniform blocks, 16
// texture units, 65 535 work groups a dimension); llvmpipe and GPUs give more, each its
// own amount. A program that needs more than the GL gives ends with exit code 4 and a
// message naming the limit, what the program needs, what the GL gives and what to do,
// instead of a driver's link error (or a silently wrong picture).
//
// Every limit can be lowered for a test, never raised: COURSE_GL_LIMIT_<NAME>=N, e.g.
// COURSE_GL_LIMIT_MAX_COMPUTE_SHADER_STORAGE_BLOCKS=8, makes this GL look like one that
// gives only the minimum.
#pragma once
#include <string>
#include <utility>
#include <vector>

#include "course/gl.h"

namespace course {

// A limit of this GL: glGetInteger64(i_v) of `name` (component `index` of an indexed
// one), lowered by COURSE_GL_LIMIT_<glName without "GL_"> when that is set and smaller.
long long glLimit(GLenum name, const char* glName, int index = -1);

// After a program of these stages has linked: checks its storage blocks, uniform
// blocks, samplers and work-group size against this GL's limits (exit code 4 when one
// is short). `label` names the program in messages.
void checkProgramLimits(GLuint program, const std::vector<GLenum>& stages,
                        const std::string& label);

// When a link failed: if a stage's source (its text, by stage) declares more storage blocks than the
// GL allows a stage, or a binding past the last, the message that says so (to go
// before the driver's own words); empty when the declarations fit. Counts what the
// source declares, #if'd out or not: a driver may count unused blocks too.
std::string explainLinkFailure(const std::vector<std::pair<GLenum, std::string>>& stages);

// What a source declares, read from its text (for explainLinkFailure and its tests).
struct DeclaredBlocks {
    int storageBlocks = 0;
    int highestStorageBinding = -1;
};
DeclaredBlocks declaredBlocks(const std::string& source);

// glDispatchCompute's group counts against GL_MAX_COMPUTE_WORK_GROUP_COUNT.
void checkWorkGroupCount(const int groups[3], const std::string& label);

}  // namespace course
