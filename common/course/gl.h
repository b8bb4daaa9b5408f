// Every GL call in the course goes through GLAD's loader, generated at build time.
#pragma once
#include <glad/gl.h>
