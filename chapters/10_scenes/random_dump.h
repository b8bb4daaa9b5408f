// --dump-random FILE --count K: the raw random numbers, for the checks. Draws K numbers
// from every pixel's generator (continuing from the state the render left) and writes
// them as little-endian uint32 in the order (number, row, column), row 0 at the top:
// numpy reads it with np.fromfile(FILE, "<u4").reshape(K, height, width).
#pragma once
#include <string>

#include "course/session.h"

void dumpRandomNumbers(course::Session& session, int width, int height, int count,
                       const std::string& path);
