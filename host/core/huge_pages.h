#pragma once
// Large arrays (control nets of 10^7 points, their V and α) backed by transparent huge pages.
//
// Linux gives a process fresh memory one 4 KiB page at a time, on the first write to each page; in
// a virtual machine every such fault is a trip through the hypervisor. A 4096² net is 400 MB:
// 100,000 faults per copy, which made building an α-EB surface take 3× as long as computing it.
// Where transparent huge pages are enabled "for madvise" (Debian's default), asking for them on the
// untouched block before it is written makes that 200 faults of 2 MiB.
#include <cstddef>
#include <vector>

namespace shapespline {

// madvise(MADV_HUGEPAGE) on the whole pages inside [data, data + bytes); nothing for blocks under
// 4 MiB or where the kernel does not support it (the advice is only advice).
void adviseHugePages(void* data, size_t bytes);

// v.reserve(n) with the new block advised before anything is written to it.
template <class T>
void reserveHuge(std::vector<T>& v, size_t n) {
  if (n <= v.capacity()) return;
  v.reserve(n);
  adviseHugePages(v.data(), n * sizeof(T));
}

// v.resize(n) (new elements value-initialised), the block advised first.
template <class T>
void resizeHuge(std::vector<T>& v, size_t n) {
  reserveHuge(v, n);
  v.resize(n);
}

}  // namespace shapespline
