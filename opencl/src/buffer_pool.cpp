#include "simpli/ocl/buffer_pool.h"

#include "simpli/error.h"
#include "simpli/ocl/device.h"

#include <cstdlib>
#include <iterator>

namespace simpli::ocl {

Buffer::~Buffer() {
  if (pool_)
    pool_->release(mem_, bytes_);
  else
    clReleaseMemObject(mem_);
}

namespace {

std::size_t defaultCacheLimit() {
  if (const char* env = std::getenv("SIMPLI_POOL_CACHE_MB"); env && *env) {
    char* end = nullptr;
    const unsigned long long mb = std::strtoull(env, &end, 10);
    if (end && *end == '\0')
      return static_cast<std::size_t>(mb) << 20;
    fail("SIMPLI_POOL_CACHE_MB='", env, "': expected a whole number of MiB");
  }
  return std::size_t{2048} << 20;
}

} // namespace

BufferPool::BufferPool(cl_context context) : context_(context), cacheLimit_(defaultCacheLimit()) {}

BufferPool::~BufferPool() {
  trim();
}

std::shared_ptr<Buffer> BufferPool::acquire(std::size_t bytes) {
  if (bytes == 0)
    bytes = 1; // OpenCL forbids zero-sized buffers; empty tensors still get a handle
  cl_mem mem = nullptr;
  if (auto it = free_.find(bytes); it != free_.end()) {
    mem = it->second;
    free_.erase(it);
    stats_.cachedBytes -= bytes;
    ++stats_.reuses;
  } else {
    cl_int status = CL_SUCCESS;
    mem = clCreateBuffer(context_, CL_MEM_READ_WRITE, bytes, nullptr, &status);
    if (status == CL_MEM_OBJECT_ALLOCATION_FAILURE || status == CL_OUT_OF_RESOURCES ||
        status == CL_INVALID_BUFFER_SIZE) {
      // Parked buffers may be what is missing: give them back and try once more.
      trim();
      mem = clCreateBuffer(context_, CL_MEM_READ_WRITE, bytes, nullptr, &status);
    }
    if (status != CL_SUCCESS)
      fail("device allocation of ", bytes, " bytes failed: ", clErrorName(status), " (",
           stats_.liveBytes, " bytes live)");
    ++stats_.allocations;
  }
  if (poison_ && poisonQueue_) {
    const cl_uchar pattern = 0xFF;
    checkCl(clEnqueueFillBuffer(poisonQueue_, mem, &pattern, 1, 0, bytes, 0, nullptr, nullptr),
            "BufferPool poison fill");
  }
  stats_.liveBytes += bytes;
  if (stats_.liveBytes > stats_.peakBytes)
    stats_.peakBytes = stats_.liveBytes;
  return std::make_shared<Buffer>(mem, bytes, this);
}

void BufferPool::release(cl_mem mem, std::size_t bytes) {
  stats_.liveBytes -= bytes;
  if (bytes > cacheLimit_) {
    clReleaseMemObject(mem); // the queue keeps it alive until its commands are done
    ++stats_.evictions;
    return;
  }
  stats_.cachedBytes += bytes;
  free_.emplace(bytes, mem);
  shrinkTo(cacheLimit_);
}

void BufferPool::shrinkTo(std::size_t bytes) {
  while (stats_.cachedBytes > bytes && !free_.empty()) {
    const auto largest = std::prev(free_.end());
    clReleaseMemObject(largest->second);
    stats_.cachedBytes -= largest->first;
    free_.erase(largest);
    ++stats_.evictions;
  }
}

void BufferPool::setCacheLimit(std::size_t bytes) {
  cacheLimit_ = bytes;
  shrinkTo(bytes);
}

void BufferPool::trim() {
  for (auto& entry : free_)
    clReleaseMemObject(entry.second);
  free_.clear();
  stats_.cachedBytes = 0;
}

} // namespace simpli::ocl
