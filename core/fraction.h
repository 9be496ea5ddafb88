// Exact positions on the lines where tiles meet. A tile at level L with r cells puts its points at
// (i·r + k) / (r·2^L) of its root; two tiles must agree on a shared point bit for bit whatever
// their rates, and a point must be recognised from either side of a base edge (t and 1 − t), so
// positions are kept as reduced fractions and turned into doubles only to evaluate. Levels stay
// below 48 and rates below 64, so every reduced value fits 64 bits; intermediate products are
// taken in 128 bits.
#pragma once

#include <cstdint>

namespace tessera {

struct Fraction {
  int64_t num = 0, den = 1;  // den > 0, gcd(num, den) = 1

  static Fraction reduce(__int128 num, __int128 den) {
    if (den < 0) num = -num, den = -den;
    __int128 a = num < 0 ? -num : num, b = den;
    while (b != 0) {
      const __int128 r = a % b;
      a = b, b = r;
    }
    if (a > 1) num /= a, den /= a;
    return {int64_t(num), int64_t(den)};
  }
  static Fraction make(int64_t num, int64_t den) { return reduce(num, den); }
  double value() const { return double(num) / double(den); }

  friend Fraction operator+(const Fraction& a, const Fraction& b) {
    return reduce(__int128(a.num) * b.den + __int128(b.num) * a.den, __int128(a.den) * b.den);
  }
  friend Fraction operator-(const Fraction& a, const Fraction& b) { return a + Fraction{-b.num, b.den}; }
  friend Fraction operator/(const Fraction& a, const Fraction& b) {
    return reduce(__int128(a.num) * b.den, __int128(a.den) * b.num);
  }
  Fraction times(int64_t k) const { return reduce(__int128(num) * k, den); }
  Fraction over(int64_t k) const { return reduce(num, __int128(den) * k); }

  friend bool operator==(const Fraction& a, const Fraction& b) { return a.num == b.num && a.den == b.den; }
  friend bool operator<(const Fraction& a, const Fraction& b) {
    return __int128(a.num) * b.den < __int128(b.num) * a.den;
  }
  friend bool operator<=(const Fraction& a, const Fraction& b) { return !(b < a); }
};

}  // namespace tessera
