#pragma once
// Linear elastic (Hooke's law, Eq. 37): the trial deviator is the answer; no yield.

#include "strength/strength_common.hpp"

namespace shatter::strength {

struct Elastic {
  static constexpr FieldSet kFields{};
  static constexpr bool kHasShear = true;
  ElasticConstants elastic{};

  template <class T>
  void return_map(T (&)[6], PlasticState<T>& st) const {
    st.deps_p = T(0.0);
  }
};

}  // namespace shatter::strength
