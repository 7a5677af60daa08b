// Counts in messages: "1 face has", "2 faces have". A warning or an error that a user reads
// should not say "1 faces"; the one rule (singular for exactly one, plural otherwise, 0 included)
// is here rather than in a conditional at each message.
#pragma once

#include <cstddef>
#include <string>

namespace shellcontract {

/// `singular` when n is 1, else `plural`: for a word that agrees with a count ("has" / "have").
inline const char* one_or_many(std::size_t n, const char* singular, const char* plural) {
  return n == 1 ? singular : plural;
}

/// The count and its noun in agreement: counted(1, "face", "faces") is "1 face",
/// counted(3, "vertex", "vertices") is "3 vertices".
inline std::string counted(std::size_t n, const char* singular, const char* plural) {
  return std::to_string(n) + " " + one_or_many(n, singular, plural);
}

}  // namespace shellcontract
