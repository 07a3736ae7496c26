#pragma once
// No strength: a fluid (or a fully molten solid). The deviator is identically zero, so the
// stress is -p I and the longitudinal speed (Eq. 13) reduces to the bulk speed.

#include "strength/strength_common.hpp"

namespace shatter::strength {

struct Hydro {
  static constexpr FieldSet kFields{};
  static constexpr bool kHasShear = false;
  ElasticConstants elastic{};  // all zero: G = 0 in Eq. 13

  template <class T>
  void return_map(T (&s)[6], PlasticState<T>& st) const {
    for (auto& c : s) c = T(0.0);
    st.deps_p = T(0.0);
  }
};

}  // namespace shatter::strength
