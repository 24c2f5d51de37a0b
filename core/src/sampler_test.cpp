// Sampling: permutations are bijections, Owen scrambling keeps Sobol's
// stratification, stratified sets cover their strata, and the streams are
// deterministic.
#include <doctest/doctest.h>

#include <set>
#include <vector>

#include "sampler.h"

using namespace gw;

TEST_CASE("permute is a bijection of [0, n) for every n and seed") {
    for (uint32_t n : {1u, 2u, 3u, 7u, 16u, 17u, 100u, 1000u, 4096u}) {
        for (uint32_t seed : {0u, 1u, 0xdeadbeefu, 0x12345678u}) {
            std::vector<int> hit(n, 0);
            for (uint32_t i = 0; i < n; ++i) {
                const uint32_t j = permute(i, n, seed);
                REQUIRE(j < n);
                ++hit[j];
            }
            for (uint32_t j = 0; j < n; ++j) CHECK(hit[j] == 1);
        }
    }
}

TEST_CASE("different seeds give different permutations") {
    const uint32_t n = 64;
    int same = 0;
    for (uint32_t i = 0; i < n; ++i) same += permute(i, n, 1) == permute(i, n, 2);
    CHECK(same < int(n) / 2);
}

TEST_CASE("Owen-scrambled Sobol points keep one point per elementary interval") {
    // The first 2^k points of the 2D Sobol sequence, scrambled, put exactly one
    // point in each of the 2^k cells of every 2^a x 2^(k-a) grid.
    for (uint32_t seed : {0u, 7u, 0xabcdef01u}) {
        const int k = 6, n = 1 << k;
        std::vector<uint32_t> xs(n), ys(n);
        for (int i = 0; i < n; ++i) {
            xs[i] = owen_scramble(reverse_bits(uint32_t(i)), seed);
            ys[i] = owen_scramble(sobol_dim1(uint32_t(i)), seed ^ 0x5bd1e995u);
        }
        for (int a = 0; a <= k; ++a) {
            std::set<uint64_t> cells;
            for (int i = 0; i < n; ++i) cells.insert((uint64_t(a ? xs[i] >> (32 - a) : 0) << 32) | (k - a ? ys[i] >> (32 - (k - a)) : 0));
            CHECK(int(cells.size()) == n);
        }
    }
}

TEST_CASE("strat2 puts point j of n in stratum j and stays in [0, 1)") {
    for (uint32_t n : {1u, 4u, 9u, 33u}) {
        for (uint32_t j = 0; j < n; ++j) {
            for (float xi : {0.0f, 0.5f, 0.99999994f}) {
                float u1, u2;
                strat2(j, n, xi, 0.7f, u1, u2);
                CHECK(u1 >= float(j) / float(n));
                CHECK(u1 < 1.0f);
                CHECK(u2 >= 0.0f);
                CHECK(u2 < 1.0f);
            }
        }
    }
}

TEST_CASE("where permute sends each i is uniform over seeds, for n that are not powers of two too") {
    for (uint32_t n : {3u, 5u, 9u, 25u, 36u}) {
        const uint32_t seeds = 2000 * n;
        for (uint32_t i : {0u, 1u, n - 1}) {
            std::vector<int> lands(n, 0);
            for (uint32_t seed = 0; seed < seeds; ++seed) ++lands[permute(i, n, mix32(seed))];
            for (int count : lands) {
                CHECK(count > 1800);   // 2000 expected, standard deviation about 45
                CHECK(count < 2200);
            }
        }
    }
}

TEST_CASE("a pixel's shared strata are each taken once, and each sample's own slots spread over the set") {
    for (uint32_t samples : {1u, 2u, 4u, 9u, 16u, 25u, 64u})
        for (uint32_t n : {1u, 3u, 8u})
            for (uint32_t key : {0u, 0x12345u, 0xdeadbeefu}) {
                std::vector<int> taken(samples * n, 0);
                for (uint32_t s = 0; s < samples; ++s)
                    for (uint32_t j = 0; j < n; ++j) {
                        const uint32_t slot = shared_slot(s, samples, key, j);
                        REQUIRE(slot < samples * n);
                        ++taken[slot];
                        CHECK(slot / samples == j);   // slot j of every sample lies in the j-th band
                    }
                for (int t : taken) CHECK(t == 1);
            }
}

TEST_CASE("streams are deterministic and distinct") {
    Rng a(stream_seed(5, Stream::Lens), 10, 3), b(stream_seed(5, Stream::Lens), 10, 3);
    Rng c(stream_seed(5, Stream::PixelSamples), 10, 3);
    int differ = 0;
    for (int i = 0; i < 16; ++i) {
        const float x = a.next(), y = b.next(), z = c.next();
        CHECK(x == y);
        CHECK(x >= 0.0f);
        CHECK(x < 1.0f);
        differ += x != z;
    }
    CHECK(differ >= 15);
}

TEST_CASE("the Gaussian filter offset stays within two standard deviations") {
    for (float u : {0.0f, 0.3f, 0.999f, 0.99999994f})
        for (float v : {0.0f, 0.25f, 0.8f}) {
            float ox, oy;
            gaussian_offset(u, v, 0.5f, ox, oy);
            CHECK(std::abs(ox) <= 1.0f);
            CHECK(std::abs(oy) <= 1.0f);
        }
}
