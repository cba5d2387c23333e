// Refusing keys nested too deep before toml++ parses them (section.hpp): the parser builds one table per
// segment of a dotted key or table header by recursion, so that a one-line file of about 30,000 segments
// overflows the stack.
#include <string>
#include <string_view>
#include <vector>

#include "section.hpp"

namespace mpm::scene_reading {

void refuse_deep_keys(std::string_view text, const std::string& file) {
  std::size_t line = 1, segments = 1;
  bool in_key = true,
       header = false;     // reading a key (at a line's start, in a [header], after '{' or ','); in one
  std::vector<char> open;  // the brackets of the values being read: '[' arrays, '{' inline tables
  const auto fail = [&] {
    throw InputError(file + ":" + std::to_string(line) + ": a key nested deeper than " +
                     std::to_string(max_key_depth) + " levels (table headers and dotted keys)");
  };
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (c == '"' || c == '\'') {  // a string, basic or literal, one-line or multi-line: skipped
      const bool multi = text.compare(i, 3, std::string(3, c)) == 0;
      const std::string end = multi ? std::string(3, c) : std::string(1, c);
      for (i += end.size(); i < text.size() && text.compare(i, end.size(), end) != 0; ++i) {
        if (text[i] == '\n') ++line;
        if (c == '"' && text[i] == '\\') ++i;  // an escaped character
      }
      i += end.size() - 1;
      continue;
    }
    if (c == '#') {  // a comment, to the end of its line
      while (i + 1 < text.size() && text[i + 1] != '\n') ++i;
      continue;
    }
    if (c == '\n') {
      ++line;
      if (open.empty()) in_key = true, header = false, segments = 1;
    } else if (c == '.' && in_key) {
      if (++segments > max_key_depth) fail();
    } else if (c == '=' && in_key && !header) {
      in_key = false;
    } else if (c == '[') {
      if (in_key && open.empty())
        header = true;  // [table] or [[array of tables]]
      else if (!in_key)
        open.push_back('[');
    } else if (c == ']') {
      if (header)
        in_key = false, header = false;
      else if (!open.empty())
        open.pop_back();
    } else if (c == '{') {
      open.push_back('{'), in_key = true, segments = 1;
    } else if (c == '}') {
      if (!open.empty()) open.pop_back();
      in_key = false;
    } else if (c == ',' && !open.empty() && open.back() == '{') {
      in_key = true, segments = 1;
    }
  }
}

}  // namespace mpm::scene_reading
