/**
 * \file core/view_buffers.h
 * What every generated model view (<name>_view.cc, templates/mechanism_view.cc.mustache) does
 * the same way: the shape of a fixed-size member (rows x cols), the members' offsets in a
 * struct's buffer (the struct's own), and the copies between a view's flat arrays
 * (column-major) and the fixed-size Eigen types, std::array and double. Written once here, read
 * by every view. Needs Eigen (fixed sizes) and the standard library.
 */
#pragma once

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <type_traits>

#include <Eigen/Core>

#include "mechgen/core/model_view.h"

namespace mechgen::view_buffers {

template <class T>
struct Shape;
template <int R, int C, int O, int MR, int MC>
struct Shape<Eigen::Matrix<double, R, C, O, MR, MC>> {
  static_assert((O & Eigen::RowMajor) == 0 || R == 1, "a view buffer is column-major");
  static constexpr int kRows = R, kCols = C;
};
template <>
struct Shape<double> {
  static constexpr int kRows = 1, kCols = 1;
};
template <std::size_t N>
struct Shape<std::array<double, N>> {
  static constexpr int kRows = static_cast<int>(N), kCols = 1;
};
// A member at byte offset `offset` of its struct, in doubles: a struct's buffer is laid out as
// the struct is (padding included), so that the struct itself may lie on it (InPlace).
template <class T>
constexpr mechgen::ViewMember Member(const char* name, std::size_t offset) {
  return {name, Shape<T>::kRows, Shape<T>::kCols, static_cast<int>(offset / sizeof(double))};
}
// The buffer's size in doubles: the struct's, padding included, rounded up. A struct with a
// double in it is a whole number of doubles (its alignment is at least a double's); one whose
// members are all empty (a model without loops: kNc = kNphi = 0, each zero-size matrix a byte)
// has no double to hold and a size of a few bytes: one double covers it.
template <class S>
constexpr int SizeOf() {
  return static_cast<int>((sizeof(S) + sizeof(double) - 1) / sizeof(double));
}

template <int R, int C, int O, int MR, int MC>
void Get(const double* b, Eigen::Matrix<double, R, C, O, MR, MC>* m) {
  for (int i = 0; i < R * C; ++i) m->data()[i] = b[i];
}
template <int R, int C, int O, int MR, int MC>
void Put(const Eigen::Matrix<double, R, C, O, MR, MC>& m, double* b) {
  for (int i = 0; i < R * C; ++i) b[i] = m.data()[i];
}
// Every entry 0: the start of an output the function writes whole (ModelView: Coeffs' out,
// Solve's and SolveTrig's trig), which is then not read from its buffer.
template <int R, int C, int O, int MR, int MC>
void Zero(Eigen::Matrix<double, R, C, O, MR, MC>* m) {
  m->setZero();
}
inline void Zero(double* x) { *x = 0; }

template <class T, std::size_t N>
void Zero(std::array<T, N>* a) {
  a->fill(T());
}
inline void Get(const double* b, double* x) { *x = *b; }
inline void Put(const double& x, double* b) { *b = x; }
template <class T, std::size_t N>
void Get(const T* b, std::array<T, N>* a) {
  for (std::size_t i = 0; i < N; ++i) (*a)[i] = b[i];
}
template <class T, std::size_t N>
void Put(const std::array<T, N>& a, T* b) {
  for (std::size_t i = 0; i < N; ++i) b[i] = a[i];
}
template <class T, std::size_t N, std::size_t M>
constexpr std::array<T, N * M> Flat(const std::array<std::array<T, M>, N>& a) {
  std::array<T, N * M> flat{};
  for (std::size_t i = 0; i < N; ++i)
    for (std::size_t j = 0; j < M; ++j) flat[i * M + j] = a[i][j];
  return flat;
}

// An output member that the function stores `stored` distinct entries of, unconditionally
// (codegen/emit.cc, StructUse): read from its buffer first unless that is every entry (then
// the function overwrites it whole, and its buffer need not be initialized).
template <int stored, class X>
void GetUnlessStored(const double* b, X* x) {
  if constexpr (stored < Shape<X>::kRows * Shape<X>::kCols) {
    Get(b, x);
  } else {
    (void)b, (void)x;
  }
}
// The same for an output the view writes whole (ModelView: Coeffs' out): set to 0 first unless
// the function stores every entry.
template <int stored, class X>
void ZeroUnlessStored(X* x) {
  if constexpr (stored < Shape<X>::kRows * Shape<X>::kCols) {
    Zero(x);
  } else {
    (void)x;
  }
}

// The reads statics::Solve makes of a member of Statics after Forces (ModelView::ForcesChecked),
// at the member's fixed size, as the generated model's own statics make them
// (statics::internal::AllFinite and MaxAbs on the fixed-size types): whether every entry at b is
// finite, and max_i |x_i| (on a copy of the fixed-size type, so that Eigen's reduction takes
// the entries in the same order, NaN included).
template <class X>
bool Finite(const double* b) {
  if constexpr (std::is_same_v<X, double>) {
    return std::isfinite(*b);
  } else {
    return Eigen::Map<const X>(b).allFinite();
  }
}
template <class X>
double MaxAbs(const double* b) {
  const X x = Eigen::Map<const X>(b);
  return x.cwiseAbs().maxCoeff();
}

// A struct on the caller's storage: the buffer b is taken as the struct S itself where S lies
// in it as its members do (kLayout: the view's k<Struct>InPlace, each member at its offset)
// and b is aligned for S (nullptr stays nullptr); the function then reads and writes the
// buffer's entries directly, with nothing copied in or out.
template <bool kLayout, class S>
bool InPlace(const double* b) {
  return kLayout && reinterpret_cast<std::uintptr_t>(b) % alignof(S) == 0;
}
template <class S>
S* At(double* b) {
  return reinterpret_cast<S*>(b);
}
template <class S>
const S* At(const double* b) {
  return reinterpret_cast<const S*>(b);
}

}  // namespace mechgen::view_buffers
