"""Chapter 09's random numbers in numpy (python_prototypes/rng.py): the generator is the
textbook hybrid Taus bit for bit, and the statistics tell the naive per-pixel seeding
(lines) from the hashed one (noise)."""

import numpy as np
import pytest

from python_prototypes import rng

WIDTH, HEIGHT, COUNT = 128, 96, 48


# ---------------------------------------------------------------------------------------
# The generator, against a scalar transcription of GPU Gems 3's code in Python integers
# ---------------------------------------------------------------------------------------

MASK = 0xFFFFFFFF


def scalar_taus(z, s1, s2, s3, m):
    b = (((z << s1) & MASK) ^ z) >> s2
    return (((z & m) << s3) & MASK) ^ b


def scalar_hybrid_taus(state):
    """One step of [z1, z2, z3, z4] (a list, changed in place); the 32-bit output."""
    state[0] = scalar_taus(state[0], 13, 19, 12, 4294967294)
    state[1] = scalar_taus(state[1], 2, 25, 4, 4294967288)
    state[2] = scalar_taus(state[2], 3, 11, 17, 4294967280)
    state[3] = (1664525 * state[3] + 1013904223) & MASK
    return state[0] ^ state[1] ^ state[2] ^ state[3]


def scalar_pcg_hash(x):
    state = (x * 747796405 + 2891336453) & MASK
    word = (((state >> ((state >> 28) + 4)) ^ state) * 277803737) & MASK
    return (word >> 22) ^ word


def scalar_wang_hash(x):
    x = (x ^ 61) ^ (x >> 16)
    x = (x * 9) & MASK
    x ^= x >> 4
    x = (x * 0x27D4EB2D) & MASK
    return x ^ (x >> 15)


def test_hashes_match_the_scalar_code():
    values = [0, 1, 2, 127, 128, 65535, 2**31, MASK, 123456789]
    assert rng.pcg_hash(values).tolist() == [scalar_pcg_hash(v) for v in values]
    assert rng.wang_hash(values).tolist() == [scalar_wang_hash(v) for v in values]
    assert rng.pcg_hash(values).dtype == np.uint32


@pytest.mark.parametrize("seeding", rng.SEEDINGS)
def test_streams_match_the_scalar_generator_bit_for_bit(seeding):
    streams = rng.pixel_streams(seeding, 42, 5, 3, 20)
    state = rng.initial_state(seeding, 42, np.arange(15))
    for pixel in [0, 1, 7, 14]:
        y, x = divmod(pixel, 5)  # pixel index = y * width + x
        scalar_state = [int(word) for word in state[:, pixel]]
        expected = [scalar_hybrid_taus(scalar_state) for _ in range(20)]
        assert streams[:, y, x].tolist() == expected


def test_seedings_follow_their_formulas():
    words = [scalar_pcg_hash(3)]
    for _ in range(3):
        words.append(scalar_pcg_hash(words[-1]))
    assert rng.seed_words(3).tolist() == words

    def raised(z):
        return z + 128 if z < 128 else z

    for pixel in [0, 1, 1000]:
        naive = [(words[k] + pixel) & MASK for k in range(4)]
        hashed = [scalar_pcg_hash((words[k] + scalar_pcg_hash(pixel)) & MASK)
                  for k in range(4)]
        assert rng.naive_state(3, pixel)[:, 0].tolist() == \
            [raised(z) for z in naive[:3]] + naive[3:]
        assert rng.hashed_state(3, pixel)[:, 0].tolist() == \
            [raised(z) for z in hashed[:3]] + hashed[3:]


def test_small_tausworthe_words_are_raised_to_128():
    # Pixel indices that bring every naive word to 0..127 and to the top of the range.
    words = rng.seed_words(9).astype(np.int64)
    pixels = np.concatenate([((-words[:, None] + np.arange(128)) & MASK).ravel(),
                             (-words - 1) & MASK])
    state = rng.naive_state(9, pixels)
    assert state[:3].min() >= 128
    assert (state[3] < 128).any()  # the LCG word may be anything


def test_unit_floats_are_exact_and_below_one():
    bits = np.array([0, 255, 256, 2**31, MASK], dtype=np.uint32)
    floats = rng.to_unit_float(bits)
    assert floats.dtype == np.float32
    assert floats.tolist() == [0.0, 0.0, 2.0**-24, 0.5, 1.0 - 2.0**-24]


def test_a_seed_reproduces_its_streams_and_another_seed_does_not():
    first = rng.pixel_streams("hashed", 5, 16, 16, 8)
    assert np.array_equal(first, rng.pixel_streams("hashed", 5, 16, 16, 8))
    assert np.mean(first == rng.pixel_streams("hashed", 6, 16, 16, 8)) < 0.01


def test_unknown_seeding_is_an_error():
    with pytest.raises(ValueError, match="naive, hashed"):
        rng.initial_state("clever", 1, [0])


# ---------------------------------------------------------------------------------------
# The statistics
# ---------------------------------------------------------------------------------------

@pytest.fixture(scope="module", params=[1, 2024])
def samples(request):
    return {seeding: rng.pixel_floats(seeding, request.param, WIDTH, HEIGHT, COUNT)
            for seeding in rng.SEEDINGS}


def test_every_seeding_passes_per_pixel_uniformity(samples):
    # The trap of the naive seeding: each pixel's stream on its own is fine.
    for seeding, u in samples.items():
        result = rng.stream_uniformity_test(u)
        assert result.passed, f"{seeding}: {result}"


@pytest.mark.parametrize("test", [
    lambda u: rng.neighbour_correlation_test(u, "x"),
    lambda u: rng.neighbour_correlation_test(u, "y"),
    lambda u: rng.neighbour_pair_uniformity_test(u, direction="x"),
    lambda u: rng.neighbour_pair_uniformity_test(u, direction="y"),
], ids=["correlation x", "correlation y", "pairs x", "pairs y"])
def test_naive_seeding_fails_what_hashed_seeding_passes(samples, test):
    naive = test(samples["naive"])
    assert not naive.passed, f"naive: {naive}"
    assert naive.statistic > 4 * naive.limit, f"naive fails only barely: {naive}"
    for seeding in ["hashed", "hashed_wang"]:
        result = test(samples[seeding])
        assert result.passed, f"{seeding}: {result}"


def test_skipping_the_first_numbers_does_not_cure_naive_seeding():
    state = rng.initial_state("naive", 1, np.arange(WIDTH * HEIGHT))
    rng.generate(state, 1000)
    later = rng.to_unit_float(rng.generate(state, COUNT)).astype(np.float64)
    result = rng.neighbour_correlation_test(later.reshape(COUNT, HEIGHT, WIDTH), "x")
    assert result.statistic > 10 * result.limit, result


def test_hashed_seeding_passes_the_stream_correlation_test(samples):
    # Correlating two pixels' streams over time is a weak test: the naive seeding fails
    # it for most seeds (--seed 1 at 256 x 256: mean r 0.046, 72 standard errors) but
    # passes it for some (--seed 2024). The tests above compare neighbours at the same
    # sample index, which is what a renderer does, and never miss.
    for seeding in ["hashed", "hashed_wang"]:
        result = rng.stream_correlation_test(samples[seeding])
        assert result.passed, f"{seeding}: {result}"


def test_naive_first_sample_shows_lines():
    # Along a row the naive first numbers barely change: the lines of the book's
    # figure. Hashed neighbours differ by 1/3 on average, as independent numbers do.
    naive = rng.first_sample_image("naive", 1, WIDTH, HEIGHT)
    hashed = rng.first_sample_image("hashed", 1, WIDTH, HEIGHT)
    naive_step = np.median(np.abs(np.diff(naive, axis=1)))
    hashed_step = np.mean(np.abs(np.diff(hashed, axis=1)))
    assert naive_step < 0.01
    assert abs(hashed_step - 1 / 3) < 0.01


def test_chi_square_p_values_are_close_to_the_tables():
    # Critical values from tables: P(chi2(15) > 30.578) = 0.01, P(chi2(63) > 82.529) = 0.05.
    assert rng.chi_square_p_value(30.578, 15) == pytest.approx(0.01, abs=0.001)
    assert rng.chi_square_p_value(82.529, 63) == pytest.approx(0.05, abs=0.001)
    assert rng.chi_square_p_value(14.339, 15) == pytest.approx(0.5, abs=0.01)


def test_command_line_writes_the_figure_and_images(tmp_path):
    rng.main(["--figure", str(tmp_path / "f.png"), "--images", str(tmp_path / "first"),
              "--width", "32", "--height", "24"])
    for name in ["f.png", "first_naive.png", "first_hashed.png"]:
        assert (tmp_path / name).stat().st_size > 100
