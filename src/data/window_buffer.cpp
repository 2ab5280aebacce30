#include "data/window_buffer.h"

#include <stdexcept>

namespace quadfdi {

WindowBuffer::WindowBuffer(std::size_t capacity, int window) : capacity_(capacity), window_(window) {}

void WindowBuffer::add(std::shared_ptr<const TrajectoryBatch> batch) {
  Chunk chunk;
  chunk.batch = std::move(batch);
  enumerateWindows(*chunk.batch, window_, chunk.windows);
  size_ += chunk.windows.size();
  chunks_.push_back(std::move(chunk));
  while (size_ > capacity_ && !chunks_.empty()) {
    Chunk& front = chunks_.front();
    const std::size_t available = front.windows.size() - front.first;
    const std::size_t excess = size_ - capacity_;
    if (excess >= available) {
      size_ -= available;
      chunks_.pop_front();
    } else {
      front.first += excess;
      size_ -= excess;
    }
  }
}

WindowBuffer::Entry WindowBuffer::at(std::size_t i) const {
  for (const Chunk& c : chunks_) {
    const std::size_t n = c.windows.size() - c.first;
    if (i < n) return {c.batch.get(), c.windows[c.first + i]};
    i -= n;
  }
  throw std::out_of_range("WindowBuffer::at");
}

void WindowBuffer::trajectories(std::vector<Trajectory>& out) const {
  out.clear();
  for (const Chunk& c : chunks_)  // a chunk's windows are grouped by trajectory, in order
    for (std::size_t i = c.first; i < c.windows.size(); ++i)
      if (i == c.first || c.windows[i].trajectory != c.windows[i - 1].trajectory)
        out.push_back({c.batch.get(), c.windows[i].trajectory});
}

std::size_t WindowBuffer::trajectoryBytes() const {
  std::size_t bytes = 0;
  for (const Chunk& c : chunks_) bytes += c.batch->bytes();
  return bytes;
}

}  // namespace quadfdi
