// The buffer pool: reuse of released buffers by size, and the cap on parked bytes.
#include "simpli/ocl/buffer_pool.h"
#include "simpli/ocl/device.h"

#include <gtest/gtest.h>

using namespace simpli;

TEST(BufferPool, ReusesBySizeAndCapsParkedBytes) {
  ocl::BufferPool& pool = ocl::Device::current().pool();
  const std::size_t previous = pool.cacheLimit();
  pool.trim();
  pool.setCacheLimit(std::size_t{1} << 20); // 1 MiB
  const std::size_t reuses = pool.stats().reuses, evictions = pool.stats().evictions;
  { auto a = pool.acquire(300000); } // parked
  EXPECT_EQ(pool.stats().cachedBytes, 300000u);
  { auto b = pool.acquire(300000); } // reused, parked again
  EXPECT_EQ(pool.stats().reuses, reuses + 1);
  {
    // Three more distinct sizes: 300000 + 3 x 400000 > 1 MiB, so the largest parked go.
    auto c = pool.acquire(400001), d = pool.acquire(400002), e = pool.acquire(400003);
  }
  EXPECT_LE(pool.stats().cachedBytes, std::size_t{1} << 20);
  EXPECT_GE(pool.stats().evictions, evictions + 1);
  { auto big = pool.acquire(std::size_t{2} << 20); } // larger than the cap: never parked
  EXPECT_LE(pool.stats().cachedBytes, std::size_t{1} << 20);
  pool.setCacheLimit(0);
  EXPECT_EQ(pool.stats().cachedBytes, 0u);
  pool.setCacheLimit(previous);
}
