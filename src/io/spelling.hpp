// Near spellings: the valid name a misspelt key most likely meant.
#pragma once
#include <string>
#include <vector>

namespace rpfem {

// Edits (insertions, deletions, substitutions, swaps of neighbours) that
// turn a into b.
int edit_distance(const std::string& a, const std::string& b);

// The candidate nearest `word` within two edits (and fewer than half its
// letters), "" if none is (or `word` itself is a candidate).
std::string nearest_spelling(const std::string& word, const std::vector<std::string>& candidates);

}  // namespace rpfem
