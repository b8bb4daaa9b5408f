// The scene on the GPU, the GL 3.3 way: the shapes in a buffer texture (TBO), the
// materials and emitters in a uniform buffer (UBO). Chapter 12 put all five arrays in
// storage buffers; GL 3.3 shaders cannot read those.
#pragma once
#include <string>

#include "course/gl.h"
#include "course/shader_program.h"
#include "gpu_scene.h"

class SceneBuffers {
public:
    // Uploads the scene. More texels than the GL's GL_MAX_TEXTURE_BUFFER_SIZE is exit
    // code 4, naming `scenePath`. (COURSE_MAX_TEXTURE_BUFFER_TEXELS lowers the limit,
    // so that the check can be tested without a giant scene.)
    SceneBuffers(const GpuScene& scene, const std::string& scenePath);
    ~SceneBuffers();
    SceneBuffers(const SceneBuffers&) = delete;
    SceneBuffers& operator=(const SceneBuffers&) = delete;

    // Connects `program`'s samplerBuffer and uniform block to these buffers.
    void bind(const course::ShaderProgram& program) const;

private:
    GLuint texelBuffer_ = 0, texelTexture_ = 0, uniformBuffer_ = 0;
};
