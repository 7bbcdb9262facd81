// alpha A x for a square matrix A whose size N is known at compile time (the
// 23 x 23 mass matrix and stiffness Jacobian in the Rosenbrock stages,
// rosenbrock_w.hpp), with the arithmetic of Eigen's matrix-vector kernel
// (general_matrix_vector_product, which Eigen calls for these sizes): each
// row's sum is one chain over the columns in order, from zero, by packet
// multiply-adds (fused where the processor has FMA) for the rows that fill
// Eigen's packets, then scaled, alpha c + 0; the N mod 2 rows left over go
// through Eigen's kernel itself (detail::eigen_scalar_row). The results are
// those of Eigen's product to the last bit on every target
// (tests/core/fixed_size_product_test.cpp) at sizes where Eigen calls that
// kernel; below about 8 it evaluates a fixed-size product coefficient by
// coefficient instead.
//
// Eigen's kernel takes the sizes at run time and runs the rows a packet or
// two at a time, each chain of N dependent multiply-adds after the previous
// one. Here all the rows' chains advance together, column by column, so their
// latencies overlap; at N = 23 that is about a third of the time.
#pragma once

#include <cmath>

#include <Eigen/Core>

namespace rover {

namespace detail {

// a * b rounded, never fused with the addition that follows it.
inline double unfused_product(double a, double b) {
  double p = a * b;
#if defined(__GNUC__) && (defined(__x86_64__) || defined(__i386__))
  asm("" : "+x"(p));
#else
  volatile double kept = p;
  p = kept;
#endif
  return p;
}

// alpha (row . x) for the one row of a column-major N x N matrix that
// Eigen's kernel leaves to scalar code, by that kernel itself (it is never
// inlined, so this runs the very instructions Eigen's product runs for that
// row): whether the compiler fuses its sum with the products depends on the
// target and its tuning (GCC keeps such chains unfused on AMD Zen and fuses
// them on Intel), and only the same code gives the same bits everywhere.
inline double eigen_scalar_row(const double* row, Eigen::Index n, const double* x, double alpha) {
  using Eigen::internal::const_blas_data_mapper;
  using LhsMapper = const_blas_data_mapper<double, Eigen::Index, Eigen::ColMajor>;
  using RhsMapper = const_blas_data_mapper<double, Eigen::Index, Eigen::RowMajor>;
  double result = 0.0;
  Eigen::internal::general_matrix_vector_product<Eigen::Index, double, LhsMapper, Eigen::ColMajor, false, double,
                                                 RhsMapper, false>::run(1, n, LhsMapper(row, n), RhsMapper(x, 1),
                                                                        &result, 1, alpha);
  return result;
}

// a * b + c as Eigen's packet multiply-add computes it: fused where Eigen
// vectorizes with FMA, else a product rounded and then a sum.
inline double packet_multiply_add(double a, double b, double c) {
#ifdef EIGEN_VECTORIZE_FMA
  return std::fma(a, b, c);
#else
  return unfused_product(a, b) + c;
#endif
}

}  // namespace detail

template <int N>
Eigen::Matrix<double, N, 1> fixed_size_product(const Eigen::Matrix<double, N, N>& a,
                                               const Eigen::Matrix<double, N, 1>& x, double alpha) {
  using Packet = Eigen::internal::packet_traits<double>::type;
  constexpr int kPacket = Eigen::internal::packet_traits<double>::size;
  static_assert(kPacket >= 2, "Eigen's kernel leaves N mod 2 rows to scalar code only with packets");
  constexpr int kPacketRows = N - N % 2;  // rows Eigen's kernel sums by packets
  constexpr int kFull = kPacketRows / kPacket;
  constexpr int kRest = kPacketRows % kPacket;  // packet rows past the full packets (even)
  using Eigen::internal::ploadu;
  using Eigen::internal::pmadd;
  using Eigen::internal::pset1;
  Eigen::Matrix<double, N, 1> out;
  Packet sums[kFull > 0 ? kFull : 1];
  for (int p = 0; p < kFull; ++p) sums[p] = pset1<Packet>(0.0);
  double rest[kRest > 0 ? kRest : 1] = {};
  for (int j = 0; j < N; ++j) {
    const double* column = a.data() + j * N;
    const Packet b = pset1<Packet>(x[j]);
    for (int p = 0; p < kFull; ++p) sums[p] = pmadd(ploadu<Packet>(column + p * kPacket), b, sums[p]);
    for (int r = 0; r < kRest; ++r)
      rest[r] = detail::packet_multiply_add(column[kFull * kPacket + r], x[j], rest[r]);
  }
  double sums_out[kFull > 0 ? kFull * kPacket : 1];
  for (int p = 0; p < kFull; ++p) Eigen::internal::pstoreu(sums_out + p * kPacket, sums[p]);
  for (int i = 0; i < kFull * kPacket; ++i) out[i] = detail::packet_multiply_add(sums_out[i], alpha, 0.0);
  for (int r = 0; r < kRest; ++r) out[kFull * kPacket + r] = detail::packet_multiply_add(rest[r], alpha, 0.0);
  if constexpr (N % 2 == 1) out[N - 1] = detail::eigen_scalar_row(a.data() + (N - 1), N, x.data(), alpha);
  return out;
}

// y + c x into y, coefficient by coefficient, with the arithmetic the
// compiler gives Eigen's y += c * x (a fused multiply-add where the processor
// has one), in a loop the compiler vectorizes: Eigen leaves a 23-vector to
// scalar code (its size is no multiple of a packet, and the build does not
// vectorize unaligned fixed-size objects).
inline double scaled_sum(double c, double x, double y) {
#ifdef __FP_FAST_FMA
  return std::fma(c, x, y);
#else
  return c * x + y;
#endif
}

template <int N>
void add_scaled(Eigen::Matrix<double, N, 1>& y, double c, const Eigen::Matrix<double, N, 1>& x) {
  double* __restrict out = y.data();
  const double* __restrict in = x.data();
  for (int k = 0; k < N; ++k) out[k] = scaled_sum(c, in[k], out[k]);
}

}  // namespace rover
