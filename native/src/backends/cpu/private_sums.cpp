#include "backends/cpu/private_sums.h"

namespace moldtex {

void PrivateSums::prepare(size_t cells, unsigned threads) {
  const unsigned others = threads > 1 ? threads - 1 : 0;
  const bool fits = others == 0 || cells * others <= kMaxBytes / sizeof(int32_t);
  if (cells == cells_ && others == others_ && fits == exclusive_) return;
  cells_ = cells;
  others_ = others;
  exclusive_ = fits;
  if (fits)
    planes_.assign(cells * others, 0);
  else
    std::vector<int32_t>().swap(planes_);
}

void PrivateSums::fold_into(int32_t* shared, ThreadPool& pool) {
  if (!exclusive_ || others_ == 0) return;
  int32_t* const planes = planes_.data();
  const size_t cells = cells_;
  const unsigned others = others_;
  pool.parallel_for(cells, 1 << 14, [=](size_t begin, size_t end) {
    for (unsigned t = 0; t < others; ++t) {
      int32_t* const plane = planes + t * cells;
      int32_t* const into = shared;
      for (size_t i = begin; i < end; ++i) {
        into[i] += plane[i];
        plane[i] = 0;
      }
    }
  });
}

}  // namespace moldtex
