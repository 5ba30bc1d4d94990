// Test helper: the zero of f in [a, b] (f(a) and f(b) of opposite signs)
// by bisection in long double, for the tests' independent references.
#pragma once

namespace lray::testing {

template <class F> long double bisectRoot(F f, long double a, long double b, int steps = 128) {
  long double fa = f(a);
  for (int k = 0; k < steps; ++k) {
    long double m = (a + b) / 2, fm = f(m);
    if ((fm < 0) == (fa < 0)) {
      a = m;
      fa = fm;
    } else {
      b = m;
    }
  }
  return (a + b) / 2;
}

} // namespace lray::testing
