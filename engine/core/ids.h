#pragma once
// Strong integer ids: a VertexId cannot be passed where a HyperarcId is expected.
#include <compare>
#include <cstdint>
#include <functional>
#include <limits>

namespace dash {

template <class Tag>
class StrongId {
 public:
  using value_type = std::uint32_t;
  static constexpr value_type kInvalid = std::numeric_limits<value_type>::max();

  constexpr StrongId() = default;
  constexpr explicit StrongId(value_type value) : value_(value) {}

  constexpr value_type value() const { return value_; }
  constexpr bool valid() const { return value_ != kInvalid; }
  constexpr auto operator<=>(const StrongId&) const = default;

 private:
  value_type value_ = kInvalid;
};

}  // namespace dash

template <class Tag>
struct std::hash<dash::StrongId<Tag>> {
  std::size_t operator()(const dash::StrongId<Tag>& id) const noexcept {
    return std::hash<std::uint32_t>{}(id.value());
  }
};
