#include "core/sim/cvode_output.hpp"

#include <nvector/nvector_serial.h>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif
#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#define PACKSIM_COMBINE_AVX 1
#endif

namespace packsim {

namespace {

// The combination for a fixed count of vectors: the coefficients and data pointers in
// registers, the sum over the vectors unrolled. Element by element, every input read
// before the output is written: z may be any of the x[i]. With SSE2 (every x86-64) two
// elements at a time: each lane does the scalar code's multiplications and additions in
// the same order, so each element gets the same bits.
template <int N>
void combineFixed(const double* c, const double* const* x, double* z, long n) {
  double k[N];
  const double* p[N];
  for (int i = 0; i < N; ++i) {
    k[i] = c[i];
    p[i] = x[i];
  }
  long j = 0;
#if defined(__SSE2__)
  __m128d kv[N];
  for (int i = 0; i < N; ++i) kv[i] = _mm_set1_pd(k[i]);
  for (; j + 2 <= n; j += 2) {
    __m128d acc = _mm_mul_pd(kv[0], _mm_loadu_pd(p[0] + j));
#pragma GCC unroll 6
    for (int i = 1; i < N; ++i) acc = _mm_add_pd(acc, _mm_mul_pd(kv[i], _mm_loadu_pd(p[i] + j)));
    _mm_storeu_pd(z + j, acc);
  }
#endif
  for (; j < n; ++j) {
    double acc = k[0] * p[0][j];
#pragma GCC unroll 6
    for (int i = 1; i < N; ++i) acc += k[i] * p[i][j];
    z[j] = acc;
  }
}

#if PACKSIM_COMBINE_AVX
// The same on a CPU with AVX (chosen at run time; the build targets plain x86-64): four
// elements at a time, each lane still the scalar code's products and sums in the same
// order (separate multiply and add: no fused multiply-add), so the same bits; half the
// instructions of the two-lane loop on a pack's state.
// The sums over the vectors are unrolled (GCC kept them as loops that reloaded each
// vector's pointer from the stack for every four elements: some 90 instructions a tick
// on a 6-cell pack's 26 values).
template <int N>
__attribute__((target("avx"))) void combineFixedAvx(const double* c, const double* const* x, double* z, long n) {
  __m256d kv[N];
  const double* p[N];
  for (int i = 0; i < N; ++i) {
    kv[i] = _mm256_set1_pd(c[i]);
    p[i] = x[i];
  }
  long j = 0;
  for (; j + 4 <= n; j += 4) {
    __m256d acc = _mm256_mul_pd(kv[0], _mm256_loadu_pd(p[0] + j));
#pragma GCC unroll 6
    for (int i = 1; i < N; ++i) acc = _mm256_add_pd(acc, _mm256_mul_pd(kv[i], _mm256_loadu_pd(p[i] + j)));
    _mm256_storeu_pd(z + j, acc);
  }
  if (j + 2 <= n) {  // two left (a pack's state often ends so): both in one two-lane pass
    __m128d acc = _mm_mul_pd(_mm256_castpd256_pd128(kv[0]), _mm_loadu_pd(p[0] + j));
#pragma GCC unroll 6
    for (int i = 1; i < N; ++i)
      acc = _mm_add_pd(acc, _mm_mul_pd(_mm256_castpd256_pd128(kv[i]), _mm_loadu_pd(p[i] + j)));
    _mm_storeu_pd(z + j, acc);
    j += 2;
  }
  for (; j < n; ++j) {
    double acc = c[0] * p[0][j];
#pragma GCC unroll 6
    for (int i = 1; i < N; ++i) acc += c[i] * p[i][j];
    z[j] = acc;
  }
}

// Whether the CPU (and the OS, which must save its registers) has AVX; libgcc's check.
const bool kHaveAvx = [] {
  __builtin_cpu_init();  // may run before libgcc's own constructor
  return __builtin_cpu_supports("avx") != 0;
}();
#endif

// The record being filled on this thread (CvodeOutputWatch), if any.
thread_local CvodeOutputRecord* tWatched = nullptr;

}  // namespace

void cvodeCombine(int nvec, const double* c, const double* const* x, double* z, long n) {
#if PACKSIM_COMBINE_AVX
  if (kHaveAvx) {
    switch (nvec) {
      case 1: return combineFixedAvx<1>(c, x, z, n);
      case 2: return combineFixedAvx<2>(c, x, z, n);
      case 3: return combineFixedAvx<3>(c, x, z, n);
      case 4: return combineFixedAvx<4>(c, x, z, n);
      case 5: return combineFixedAvx<5>(c, x, z, n);
      case 6: return combineFixedAvx<6>(c, x, z, n);
      default: break;
    }
  }
#endif
  switch (nvec) {
    case 1: return combineFixed<1>(c, x, z, n);
    case 2: return combineFixed<2>(c, x, z, n);
    case 3: return combineFixed<3>(c, x, z, n);
    case 4: return combineFixed<4>(c, x, z, n);
    case 5: return combineFixed<5>(c, x, z, n);
    case 6: return combineFixed<6>(c, x, z, n);
    default: break;
  }
  for (long j = 0; j < n; ++j) {
    double acc = c[0] * x[0][j];
    for (int i = 1; i < nvec; ++i) acc += c[i] * x[i][j];
    z[j] = acc;
  }
}

int cvodeOutputCombination(int nvec, realtype* c, N_Vector* X, N_Vector z) {
  if (nvec < 1) return -1;
  constexpr int kMax = CvodeOutputRecord::kMaxVectors;
  const double* x[kMax];
  CvodeOutputRecord* rec = tWatched != nullptr && tWatched->z == z ? tWatched : nullptr;
  if (rec) rec->nvec = nvec <= kMax ? nvec : 0;
  if (nvec > kMax) {  // not CVODE's output (at most q+1 = 6 vectors): element by element as above
    const sunindextype n = NV_LENGTH_S(z);
    double* zd = NV_DATA_S(z);
    for (sunindextype j = 0; j < n; ++j) {
      double acc = c[0] * NV_DATA_S(X[0])[j];
      for (int i = 1; i < nvec; ++i) acc += c[i] * NV_DATA_S(X[i])[j];
      zd[j] = acc;
    }
    return 0;
  }
  for (int i = 0; i < nvec; ++i) {
    x[i] = NV_DATA_S(X[i]);
    if (rec) rec->x[i] = x[i];
  }
  cvodeCombine(nvec, c, x, NV_DATA_S(z), NV_LENGTH_S(z));
  return 0;
}

CvodeOutputWatch::CvodeOutputWatch(CvodeOutputRecord& rec) { tWatched = &rec; }
CvodeOutputWatch::~CvodeOutputWatch() { tWatched = nullptr; }

void cvodeInterpolate(const CvodeOutputRecord& rec, double t, double tn, double h, double* z, long n) {
  constexpr int kMax = CvodeOutputRecord::kMaxVectors;
  const int q = rec.nvec - 1;
  const double s = (t - tn) / h;
  // CVodeGetDky's loop for k = 0 forms s^j as 1 multiplied by s j times; s^j = s^(j-1)·s
  // is that very sequence of products, so each power is the last one times s (one
  // multiply each instead of a nested loop: some 60 instructions a tick). zn[q] first.
  double c[kMax];
  double power = 1.0;
  c[q] = power;
  for (int v = q - 1; v >= 0; --v) {
    power *= s;
    c[v] = power;
  }
  cvodeCombine(rec.nvec, c, rec.x, z, n);
}

}  // namespace packsim
