// Storage of the per-pair arrays (neighbour lists, candidate rows, cached pair coefficients): a
// std::vector whose large blocks (>= 2 MiB) are 2 MiB-aligned and advised to the kernel as
// transparent huge pages (madvise(MADV_HUGEPAGE)), so that on a Linux machine whose THP mode is
// "madvise" (Debian's default) the tens of MB a pair list takes are backed by 2 MiB pages: 512x
// fewer page faults when the list is first touched or grows, and fewer TLB misses while the loops
// stream it. Where THP is "always" this changes nothing, where it is "never" madvise is ignored;
// the values stored, and so every result, are the same either way. Measured on the ALSPH step
// (docs/alsph.md, "Folded volumes, single-precision coefficients, huge pages").
#pragma once

#include <cstddef>
#include <cstdlib>
#include <new>
#include <vector>

#include <sys/mman.h>

namespace sph {

template <class T>
struct HugePageAllocator {
  using value_type = T;
  static constexpr std::size_t huge = std::size_t{2} << 20;

  HugePageAllocator() = default;
  template <class U>
  HugePageAllocator(const HugePageAllocator<U>&) noexcept {}

  T* allocate(std::size_t n) {
    const std::size_t bytes = n * sizeof(T);
    if (bytes < huge)
      return static_cast<T*>(::operator new (bytes, std::align_val_t{alignof(T)}));
    const std::size_t size = (bytes + huge - 1) / huge * huge;
    void* p = std::aligned_alloc(huge, size);
    if (!p)
      throw std::bad_alloc();
    madvise(p, size, MADV_HUGEPAGE); // advice only: its failure leaves ordinary pages
    return static_cast<T*>(p);
  }
  void deallocate(T* p, std::size_t n) noexcept {
    if (n * sizeof(T) < huge)
      ::operator delete (p, std::align_val_t{alignof(T)});
    else
      std::free(p);
  }
  template <class U>
  bool operator==(const HugePageAllocator<U>&) const noexcept {
    return true;
  }
};

template <class T>
using PairArray = std::vector<T, HugePageAllocator<T>>;

} // namespace sph
