// Counts every global operator new of the test binary that includes this header, so a test can
// assert that a step (a controller's compute(), the QP solve) does not touch the heap. It
// *defines* the replacement operators: include it from exactly one file of an executable.
// Eigen's dynamic matrices use malloc and are not seen; the code under test uses fixed sizes.
#pragma once

#include <atomic>
#include <cstdlib>
#include <new>

namespace quadfdi::test {
inline std::atomic<long> heap_allocations{0};
}  // namespace quadfdi::test

void* operator new(std::size_t size) {
  quadfdi::test::heap_allocations.fetch_add(1, std::memory_order_relaxed);
  if (void* ptr = std::malloc(size == 0 ? 1 : size)) return ptr;
  throw std::bad_alloc();
}
// Not inlined: GCC's -Wmismatched-new-delete would otherwise see free() on a pointer from
// operator new at the call site.
[[gnu::noinline]] void operator delete(void* ptr) noexcept { std::free(ptr); }
[[gnu::noinline]] void operator delete(void* ptr, std::size_t) noexcept { std::free(ptr); }
