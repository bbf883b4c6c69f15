#include "simpli/ocl/buffer_pool.h"

#include "simpli/error.h"
#include "simpli/ocl/device.h"

namespace simpli::ocl {

Buffer::~Buffer() {
  if (pool_)
    pool_->release(mem_, bytes_);
  else
    clReleaseMemObject(mem_);
}

BufferPool::BufferPool(cl_context context) : context_(context) {}

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
  stats_.cachedBytes += bytes;
  free_.emplace(bytes, mem);
}

void BufferPool::trim() {
  for (auto& entry : free_)
    clReleaseMemObject(entry.second);
  free_.clear();
  stats_.cachedBytes = 0;
}

} // namespace simpli::ocl
