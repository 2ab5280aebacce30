// Algorithm 1's FIFO buffer: the newest `capacity` windows over the trajectories generated so
// far. Trajectories are kept once; windows are (batch, trajectory, end) views into them.
#pragma once

#include <cstddef>
#include <deque>
#include <memory>
#include <vector>

#include "data/trajectory_batch.h"

namespace quadfdi {

class WindowBuffer {
 public:
  // capacity: most windows kept [windows]; window: T [samples].
  WindowBuffer(std::size_t capacity, int window);

  // Appends every window of `batch` (ends k ∈ [max(T, F), length − 1]) and drops the oldest
  // windows beyond capacity; batches with no window left are released.
  void add(std::shared_ptr<const TrajectoryBatch> batch);

  std::size_t size() const { return size_; }
  std::size_t capacity() const { return capacity_; }
  int window() const { return window_; }
  // The i-th window, oldest first (0 ≤ i < size()).
  struct Entry {
    const TrajectoryBatch* batch;
    WindowRef ref;
  };
  Entry at(std::size_t i) const;
  // Every trajectory with at least one window in the buffer, oldest first, each once (dense
  // training of causal networks reads whole trajectories, docs/networks.md).
  struct Trajectory {
    const TrajectoryBatch* batch;
    std::int32_t index;
  };
  void trajectories(std::vector<Trajectory>& out) const;
  std::size_t batchCount() const { return chunks_.size(); }
  std::size_t trajectoryBytes() const;  // memory held by the trajectories behind the windows

 private:
  struct Chunk {
    std::shared_ptr<const TrajectoryBatch> batch;
    std::vector<WindowRef> windows;
    std::size_t first = 0;  // windows before this index were dropped
  };
  std::size_t capacity_;
  int window_;
  std::deque<Chunk> chunks_;
  std::size_t size_ = 0;
};

}  // namespace quadfdi
