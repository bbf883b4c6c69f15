#pragma once
// Reuses device buffers: a released buffer goes back to a free list keyed by its byte size and
// is handed out again for the next request of the same size. Network passes allocate the same
// shapes every step, so after the first step allocation stops. The parked bytes are capped
// (cacheLimit, default 2 GiB or SIMPLI_POOL_CACHE_MB): training with varying view counts and
// image sizes meets ever new sizes, and an uncapped cache would keep all of them.
#include <CL/cl.h>

#include <cstddef>
#include <map>
#include <memory>
#include <vector>

namespace simpli::ocl {

/// A device allocation that returns itself to its pool when the last reference dies.
class Buffer {
public:
  Buffer(cl_mem mem, std::size_t bytes, class BufferPool* pool)
      : mem_(mem), bytes_(bytes), pool_(pool) {}
  ~Buffer();
  Buffer(const Buffer&) = delete;
  Buffer& operator=(const Buffer&) = delete;
  cl_mem mem() const { return mem_; }
  std::size_t bytes() const { return bytes_; }

private:
  cl_mem mem_;
  std::size_t bytes_;
  BufferPool* pool_;
};

struct PoolStats {
  std::size_t liveBytes = 0;   ///< bytes held by live buffers
  std::size_t peakBytes = 0;   ///< maximum of liveBytes since the last resetPeak()
  std::size_t cachedBytes = 0; ///< bytes parked in free lists
  std::size_t allocations = 0; ///< clCreateBuffer calls
  std::size_t reuses = 0;      ///< requests served from a free list
  std::size_t evictions = 0;   ///< parked buffers released to respect the cache limit
};

class BufferPool {
public:
  explicit BufferPool(cl_context context);
  ~BufferPool();
  BufferPool(const BufferPool&) = delete;
  BufferPool& operator=(const BufferPool&) = delete;

  /// A buffer of at least `bytes` bytes (exactly that size; zero-byte requests get 1 byte).
  std::shared_ptr<Buffer> acquire(std::size_t bytes);
  /// Test aid: when on, every acquired buffer is first filled with 0xFF bytes, a NaN in both
  /// float32 and float64, so elements an op forgets to write show up as NaN.
  void setPoison(bool on) { poison_ = on; }
  bool poison() const { return poison_; }
  /// Releases every parked buffer back to the driver.
  void trim();
  /// Caps the bytes parked in free lists (largest parked buffers are released first).
  void setCacheLimit(std::size_t bytes);
  std::size_t cacheLimit() const { return cacheLimit_; }
  const PoolStats& stats() const { return stats_; }
  void resetPeak() { stats_.peakBytes = stats_.liveBytes; }

private:
  friend class Buffer;
  void release(cl_mem mem, std::size_t bytes);
  void shrinkTo(std::size_t bytes);
  cl_context context_;
  std::size_t cacheLimit_;
  std::multimap<std::size_t, cl_mem> free_;
  PoolStats stats_;
  bool poison_ = false;
  cl_command_queue poisonQueue_ = nullptr;

public:
  /// The queue used for poisoning (set by the Device that owns the pool).
  void setQueue(cl_command_queue queue) { poisonQueue_ = queue; }
};

} // namespace simpli::ocl
