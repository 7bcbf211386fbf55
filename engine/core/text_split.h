#pragma once
// Splitting a list held in one string ("a,b,c"; tags joined by the unit separator).
#include <string>
#include <vector>

namespace dash {

enum class EmptyItems { kKeep, kDrop };

/// The items of `text` between `separator`s. An empty `text` has no items either way.
inline std::vector<std::string> splitList(const std::string& text, char separator, EmptyItems empty) {
  std::vector<std::string> out;
  if (text.empty()) return out;
  std::size_t start = 0;
  while (true) {
    const std::size_t end = text.find(separator, start);
    std::string item = text.substr(start, end == std::string::npos ? std::string::npos : end - start);
    if (empty == EmptyItems::kKeep || !item.empty()) out.push_back(std::move(item));
    if (end == std::string::npos) return out;
    start = end + 1;
  }
}

}  // namespace dash
