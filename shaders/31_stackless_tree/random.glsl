// Random numbers on the GPU: every pixel owns a generator, the "hybrid Taus" of
// GPU Gems 3 (chapter 37), whose state of four 32-bit words lives in a storage buffer
// between dispatches. Bit for bit the same as python_prototypes/rng.py, which the
// chapter 09 checks compare it with. The later chapters use it unchanged.

// --8<-- [start:state]
// Three Tausworthe generators (x, y, z) and one linear congruential generator (w),
// stepped together. Each alone is weak; XORed, their periods multiply (about 2^121).
struct RandomState {
    uvec4 words;
};
// --8<-- [end:state]

// --8<-- [start:generator]
// One Tausworthe step: a linear shift-and-XOR recurrence on the bits of z. The mask
// drops the low bits that are not part of this generator's state.
uint tausStep(inout uint z, int s1, int s2, int s3, uint mask) {
    uint b = ((z << s1) ^ z) >> s2;
    z = ((z & mask) << s3) ^ b;
    return z;
}

// One LCG step; uint arithmetic wraps around modulo 2^32, as C and numpy's uint32 do.
uint lcgStep(inout uint z) {
    z = 1664525u * z + 1013904223u;
    return z;
}

// The next 32 random bits of this pixel's stream; advances the state.
uint nextRandom(inout RandomState state) {
    return tausStep(state.words.x, 13, 19, 12, 4294967294u)
         ^ tausStep(state.words.y, 2, 25, 4, 4294967288u)
         ^ tausStep(state.words.z, 3, 11, 17, 4294967280u)
         ^ lcgStep(state.words.w);
}

// A float in [0, 1): the top 24 bits, which a float holds exactly, times 2^-24. (The
// textbook's x * 2.3283064365387e-10 rounds x near 2^32 up to 1.0 in float32.)
float random01(inout RandomState state) {
    return float(nextRandom(state) >> 8) * (1.0 / 16777216.0);
}
// --8<-- [end:generator]

// --8<-- [start:seeding]
// The PCG hash (Jarzynski and Olano, JCGT 2020): an LCG step, then a permutation that
// lets the high bits reshuffle the low ones. Inputs 1 apart give unrelated outputs.
uint pcgHash(uint x) {
    uint state = x * 747796405u + 2891336453u;
    uint word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

// The four seed words of the whole image, from --seed: a chain of hashes.
uvec4 seedWords(uint seed) {
    uvec4 s;
    s.x = pcgHash(seed);
    s.y = pcgHash(s.x);
    s.z = pcgHash(s.y);
    s.w = pcgHash(s.z);
    return s;
}

// A Tausworthe word below 128 keeps zeros in its low bits for many steps (0 forever):
// both seedings move such a word up by 128.
RandomState raiseSmallWords(uvec4 words) {
    bvec3 small = lessThan(words.xyz, uvec3(128u));
    words.xyz = words.xyz + uvec3(small) * 128u;
    return RandomState(words);
}

// Naive: each word is the seed word plus the pixel's index. Neighbours start 1 apart
// and their streams stay related for ever: stripes.
RandomState seedNaive(uint seed, uint pixelIndex) {
    return raiseSmallWords(seedWords(seed) + uvec4(pixelIndex));
}

// Hashed: the pixel index is hashed, added to the seed word, and hashed again, so
// neighbouring pixels start from unrelated states.
RandomState seedHashed(uint seed, uint pixelIndex) {
    uvec4 s = seedWords(seed);
    uint p = pcgHash(pixelIndex);
    return raiseSmallWords(uvec4(pcgHash(s.x + p), pcgHash(s.y + p), pcgHash(s.z + p),
                                 pcgHash(s.w + p)));
}
// --8<-- [end:seeding]
