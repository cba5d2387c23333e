// Equation citations in the comments of include/, src/ and apps/ (read as text from MPM_SOURCE_DIR) against
// the canonical form `Author Year, Eq. (N)` and against the tables of docs/equations.md, which describes the
// form and these checks. Comments of consecutive lines are joined into blocks and split into sentences; an
// equation's paper is the nearest author-year before it in its sentence.
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;

const fs::path kRoot = MPM_SOURCE_DIR;

struct Citation {
  std::string paper, equation, file;
  auto operator<=>(const Citation&) const = default;
};

std::string describe(const Citation& c) {
  return c.paper + ", Eq. (" + c.equation + ") in " + c.file;
}

/// Consecutive comment lines joined by single spaces; starts[k] is where line first_line + k begins in text.
struct Comment {
  int first_line = 0;
  std::string text;
  std::vector<std::size_t> starts;

  int line_of(std::size_t offset) const {
    const auto after = std::upper_bound(starts.begin(), starts.end(), offset);
    return first_line + static_cast<int>(after - starts.begin()) - 1;
  }
};

/// Groups comment lines into Comments: a blank comment line ends a block, and a line comment continues the
/// block above only if it follows it on the next line with nothing before it (a comment after code starts
/// one).
class CommentBlocks {
 public:
  void line_comment(int line, bool alone, std::string_view body) {
    const bool continues = open_ && alone && line == last_line_ + 1;
    add(line, continues, body.substr(std::min(body.find_first_not_of("/!<"), body.size())));
  }
  void block_comment(int line, std::string_view body) {  // body: between /* and */, or """ and """
    open_ = false;
    std::istringstream lines{std::string(body)};
    for (std::string text; std::getline(lines, text); ++line)
      add(line, open_,
          std::string_view(text).substr(std::min(text.find_first_not_of(" \t*!<"), text.size())));
    open_ = false;
  }
  std::vector<Comment> take() { return std::move(blocks_); }

 private:
  void add(int line, bool continues, std::string_view body) {
    const std::size_t first = body.find_first_not_of(" \t\r"), last = body.find_last_not_of(" \t\r");
    open_ = first != std::string_view::npos;
    last_line_ = line;
    if (!open_) return;
    if (!continues) blocks_.push_back(Comment{line, "", {}});
    Comment& c = blocks_.back();
    if (!c.text.empty()) c.text += ' ';
    c.starts.push_back(c.text.size());
    c.text += body.substr(first, last - first + 1);
  }
  std::vector<Comment> blocks_;
  bool open_ = false;
  int last_line_ = 0;
};

/// The comments of a C++ (python = false) or Python source: string and character literals are skipped.
std::vector<Comment> comments_of(const std::string& src, bool python) {
  CommentBlocks blocks;
  const std::string_view text(src);
  int line = 1;
  std::size_t line_begin = 0;
  const auto block = [&](std::size_t i, std::size_t open, const std::string& close) {  // returns its end
    const std::size_t end = std::min(text.find(close, i + open), text.size());
    blocks.block_comment(line, text.substr(i + open, end - i - open));
    line += static_cast<int>(std::count(text.begin() + static_cast<std::ptrdiff_t>(i),
                                        text.begin() + static_cast<std::ptrdiff_t>(end), '\n'));
    return end + close.size();
  };
  for (std::size_t i = 0; i < text.size();) {
    const std::string_view rest = text.substr(i);
    if (text[i] == '\n') {
      ++line, line_begin = ++i;
    } else if (python ? text[i] == '#' : rest.starts_with("//")) {
      const std::size_t end = std::min(text.find('\n', i), text.size());
      blocks.line_comment(line, text.find_first_not_of(" \t", line_begin) == i,
                          text.substr(i + 1, end - i - 1));
      i = end;
    } else if (!python && rest.starts_with("/*")) {
      i = block(i, 2, "*/");
    } else if (python && (rest.starts_with("\"\"\"") || rest.starts_with("'''"))) {
      i = block(i, 3, std::string(rest.substr(0, 3)));
    } else if ((text[i] == '"' || text[i] == '\'') &&
               !(i > 0 && std::isdigit(static_cast<unsigned char>(text[i - 1])))) {
      std::size_t j = i + 1;  // a literal ends at its quote or, unterminated, at the end of its line
      while (j < text.size() && text[j] != text[i] && text[j] != '\n') j += text[j] == '\\' ? 2 : 1;
      i = j < text.size() && text[j] == '\n' ? j : j + 1;
    } else {
      ++i;
    }
  }
  return blocks.take();
}

/// [begin, end) of each sentence: a sentence ends at . ! or ? followed by a space and a capital letter,
/// unless the word before the period is an abbreviation (Eq., et al., Sec., e.g., an initial).
std::vector<std::pair<std::size_t, std::size_t>> sentences(const std::string& text) {
  static const std::set<std::string> abbreviations = {"Eq",   "Eqs", "al",   "Sec", "Secs", "Fig",
                                                      "Figs", "Alg", "Algs", "App", "e.g",  "i.e",
                                                      "cf",   "vs",  "Ref",  "No"};
  std::vector<std::pair<std::size_t, std::size_t>> out;
  std::size_t begin = 0;
  for (std::size_t i = 0; i + 2 < text.size(); ++i) {
    if (std::string_view(".!?").find(text[i]) == std::string_view::npos || text[i + 1] != ' ' ||
        !std::isupper(static_cast<unsigned char>(text[i + 2])))
      continue;
    std::size_t w = i;
    while (w > begin && (std::isalpha(static_cast<unsigned char>(text[w - 1])) || text[w - 1] == '.')) --w;
    const std::string word = text.substr(w, i - w);
    if (text[i] == '.' && (abbreviations.contains(word) || (word.size() == 1 && std::isupper(word[0]))))
      continue;
    out.emplace_back(begin, i + 1);
    begin = i + 2;
  }
  out.emplace_back(begin, text.size());
  return out;
}

const std::regex kAuthorYear(R"([A-Z][a-z]+(?: & [A-Z][a-z]+| et al\.)? (?:19|20)\d\d\b)");
const std::regex kMention(R"(\bEqs?\b\.?\s*[(\d])");
const std::regex kCanonical(R"(Eq\. \(((?:[A-Z]\.)?\d+(?:\.\d+)*)\))");
const std::regex kBareNumberAfter(R"(\s*(?:(?:-|–|,|and|or|to)\s*\((?:[A-Z]\.)?\d|(?:-|–)\s*\d))");
constexpr auto kAtStart = std::regex_constants::match_continuous;
const std::regex kRangeEnd(R"( to Eq\. \(((?:[A-Z]\.)?\d+(?:\.\d+)*)\))");

/// The equations strictly between first and last when they differ only in their last number (2.1.9, 2.1.12).
std::vector<std::string> between(const std::string& first, const std::string& last) {
  const std::size_t a = first.rfind('.') + 1, b = last.rfind('.') + 1;  // npos + 1 == 0: no prefix
  if (first.substr(0, a) != last.substr(0, b) || !std::isdigit(static_cast<unsigned char>(first[a])))
    return {};
  std::vector<std::string> out;
  for (int k = std::stoi(first.substr(a)) + 1; k < std::stoi(last.substr(b)); ++k)
    out.push_back(first.substr(0, a) + std::to_string(k));
  return out;
}

struct Scan {
  std::set<Citation> citations;
  std::vector<std::string> violations;  // "file:line: what: excerpt"
  std::set<std::string> files_with_violations;
};

void scan_source(const std::string& file, const std::string& src, bool python, Scan& scan) {
  const auto flag = [&](const Comment& c, std::size_t at, const std::string& what) {
    scan.violations.push_back(file + ":" + std::to_string(c.line_of(at)) + ": " + what + ": \"" +
                              c.text.substr(at >= 30 ? at - 30 : 0, 70) + "\"");
    scan.files_with_violations.insert(file);
  };
  for (const Comment& c : comments_of(src, python)) {
    for (const auto& [begin, end] : sentences(c.text)) {
      const std::string sentence = c.text.substr(begin, end - begin);
      std::vector<std::pair<std::size_t, std::string>> authors;  // (end offset, author-year)
      for (std::sregex_iterator it(sentence.begin(), sentence.end(), kAuthorYear), last; it != last; ++it)
        authors.emplace_back(static_cast<std::size_t>(it->position() + it->length()), it->str());
      for (std::sregex_iterator it(sentence.begin(), sentence.end(), kMention), last; it != last; ++it) {
        const std::size_t at = begin + static_cast<std::size_t>(it->position());
        std::smatch eq, range;
        const bool canonical =
            std::regex_search(sentence.cbegin() + it->position(), sentence.cend(), eq, kCanonical, kAtStart);
        const auto author = std::find_if(authors.rbegin(), authors.rend(), [&](const auto& a) {
          return a.first <= static_cast<std::size_t>(it->position());
        });
        const char* problem = !canonical ? "not in the form Eq. (N)"
                              : std::regex_search(eq[0].second, sentence.cend(), kBareNumberAfter, kAtStart)
                                  ? "a second equation number without its own Eq. ( )"
                              : c.line_of(at) != c.line_of(at + static_cast<std::size_t>(eq.length()) - 1)
                                  ? "split across lines"
                              : author == authors.rend() ? "no author-year before it in its sentence"
                                                         : nullptr;
        if (problem) {
          flag(c, at, problem);
          continue;
        }
        scan.citations.insert({author->second, eq[1], file});
        if (std::regex_search(eq[0].second, sentence.cend(), range, kRangeEnd, kAtStart))
          for (const std::string& inner : between(eq[1], range[1]))
            scan.citations.insert({author->second, inner, file});
      }
    }
  }
}

std::string read(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// Every .hpp/.cpp/.py under include/, src/ and apps/ of the source tree.
Scan scan_tree() {
  std::vector<fs::path> files;
  for (const char* dir : {"include", "src", "apps"})
    for (const fs::directory_entry& e : fs::recursive_directory_iterator(kRoot / dir))
      if (e.is_regular_file() &&
          std::set<std::string>{".hpp", ".cpp", ".py"}.contains(e.path().extension().string()))
        files.push_back(e.path());
  std::sort(files.begin(), files.end());
  Scan scan;
  for (const fs::path& f : files)
    scan_source(fs::relative(f, kRoot).generic_string(), read(f), f.extension() == ".py", scan);
  return scan;
}

/// The rows of docs/equations.md: table rows `| Eq. (N) | what it is | where |` under a `## ` heading that
/// names the paper's author-year; where is a comma-separated list of files, backticks allowed.
std::set<Citation> documented(const std::string& markdown) {
  static const std::regex row(R"(^\|\s*Eq\. \(([^)]+)\)\s*\|[^|]*\|([^|]*)\|\s*$)");
  std::set<Citation> out;
  std::string paper, line;
  std::istringstream in(markdown);
  while (std::getline(in, line)) {
    std::smatch m;
    if (line.starts_with("## ")) {
      paper = std::regex_search(line, m, kAuthorYear) ? m.str() : "";
    } else if (std::regex_match(line, m, row)) {
      std::istringstream where(m.str(2));
      for (std::string file; std::getline(where, file, ',');) {
        std::erase_if(file,
                      [](char ch) { return ch == '`' || std::isspace(static_cast<unsigned char>(ch)); });
        if (!file.empty()) out.insert({paper, m.str(1), file});
      }
    }
  }
  return out;
}

std::string listing(const std::vector<std::string>& items) {
  std::string out;
  for (const std::string& s : items) out += "\n  " + s;
  return out;
}

// The parser on a snippet with known content: four violations (Eq. (14) in a sentence without an
// author-year; Eqs 7-8, found after a digit separator; a bare second number and a citation split across
// lines in a block comment), a string literal that is not a comment, and a range 2.4.1 to 2.4.3 that cites
// three equations.
TEST(Citations, ParserFindsKnownCitationsAndViolationsInASnippet) {
  const std::string snippet =
      "/// Wallstedt & Guilkey 2008, Eq. (8), Eq. (9). The force\n"
      "/// follows (Eq. (14)).\n"
      "const char* s = \"// Eq. 5\";  // Sulsky & Kaul 2004, Eq. (2.4.1) to\n"
      "                             // Eq. (2.4.3)\n"
      "int n = 1'000;  // Eqs 7-8\n"
      "/* Sulsky & Kaul 2004, Eq. (2.1.13)-(2.1.14), Eq.\n"
      "   (2.1.15) */\n";
  Scan scan;
  scan_source("snippet.hpp", snippet, false, scan);
  ASSERT_EQ(scan.violations.size(), 4u) << listing(scan.violations);
  EXPECT_TRUE(scan.violations[0].starts_with("snippet.hpp:2: no author-year")) << scan.violations[0];
  EXPECT_TRUE(scan.violations[1].starts_with("snippet.hpp:5: not in the form")) << scan.violations[1];
  EXPECT_TRUE(scan.violations[2].starts_with("snippet.hpp:6: a second equation")) << scan.violations[2];
  EXPECT_TRUE(scan.violations[3].starts_with("snippet.hpp:6: split across lines")) << scan.violations[3];
  const std::set<Citation> expected = {{"Sulsky & Kaul 2004", "2.4.1", "snippet.hpp"},
                                       {"Sulsky & Kaul 2004", "2.4.2", "snippet.hpp"},
                                       {"Sulsky & Kaul 2004", "2.4.3", "snippet.hpp"},
                                       {"Wallstedt & Guilkey 2008", "8", "snippet.hpp"},
                                       {"Wallstedt & Guilkey 2008", "9", "snippet.hpp"}};
  EXPECT_EQ(scan.citations, expected);
}

// Every equation mention in include/, src/, apps/ is canonical and attributed: zero violations.
TEST(Citations, EveryEquationMentionIsCanonicalWithAnAuthorYear) {
  const Scan scan = scan_tree();
  EXPECT_EQ(scan.violations.size(), 0u) << "non-canonical equation citations:" << listing(scan.violations);
}

// The (paper, equation, file) triples of the code equal the rows of docs/equations.md. Files that have
// violations are left out here (their citations cannot all be read); the test above reports them.
TEST(Citations, DocsTablesListExactlyTheCitationsInTheCode) {
  const Scan scan = scan_tree();
  const auto skipped = [&](const Citation& c) { return scan.files_with_violations.contains(c.file); };
  std::set<Citation> docs = documented(read(kRoot / "docs" / "equations.md")), code = scan.citations;
  EXPECT_GT(docs.size(), 100u);  // the tables have well over a hundred (paper, equation, file) rows
  std::erase_if(docs, skipped);
  std::erase_if(code, skipped);
  std::vector<std::string> missing, extra;
  for (const Citation& c : code)
    if (!docs.contains(c)) missing.push_back(describe(c));
  for (const Citation& c : docs)
    if (!code.contains(c)) extra.push_back(describe(c));
  EXPECT_EQ(missing.size(), 0u) << "cited in the code, not in docs/equations.md:" << listing(missing);
  EXPECT_EQ(extra.size(), 0u) << "in docs/equations.md, not cited in the code:" << listing(extra);
}

// Known citations of the tree, so that a parser that found nothing could not pass: the Neo-Hookean stresses
// (Wallstedt & Guilkey 2008, Eq. (54), Eq. (55)), the matrix-free directional derivative, the boundary
// acceleration, and Eq. (2.1.12), which only the range Eq. (2.1.9) to Eq. (2.1.19) of elastoplastic.hpp
// cites.
TEST(Citations, KnownCitationsAreFound) {
  const Scan scan = scan_tree();
  const std::vector<Citation> known = {
      {"Wallstedt & Guilkey 2008", "55", "include/mpm/materials/neo_hookean.hpp"},
      {"Wallstedt & Guilkey 2008", "54", "include/mpm/materials/neo_hookean.hpp"},
      {"Sulsky & Kaul 2004", "2.4.18", "src/numerics/newton_krylov.cpp"},
      {"Steffen et al. 2008", "30", "src/boundary/boundary.cpp"},
      {"Sulsky & Kaul 2004", "2.1.12", "include/mpm/materials/elastoplastic.hpp"},
  };
  for (const Citation& c : known) EXPECT_TRUE(scan.citations.contains(c)) << describe(c);
}

}  // namespace
