#include "markdown_quotes.hpp"

#include <algorithm>
#include <cctype>
#include <map>
#include <regex>
#include <sstream>

namespace causal::docs {
namespace {

std::vector<std::string> split_lines(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r");
  if (b == std::string::npos) return "";
  const auto e = s.find_last_not_of(" \t\r");
  return s.substr(b, e - b + 1);
}

bool is_fence(const std::string& trimmed) {
  return trimmed.rfind("```", 0) == 0 || trimmed.rfind("~~~", 0) == 0;
}

bool is_shell_info(std::string info) {
  info = trim(info);
  return info == "sh" || info == "bash" || info == "shell" || info == "console";
}

// "## Many hosts ##" -> "Many hosts"; "" when the line is not an ATX heading.
std::string heading_text(const std::string& line) {
  std::size_t hashes = 0;
  while (hashes < line.size() && line[hashes] == '#') ++hashes;
  if (hashes == 0 || hashes > 6 || hashes >= line.size() || line[hashes] != ' ') return "";
  std::string text = trim(line.substr(hashes + 1));
  while (!text.empty() && text.back() == '#') text.pop_back();
  return trim(text);
}

// Code spans of the non-fenced text (fence lines blanked, so offsets keep their line numbers). Each span is
// replaced by spaces in `prose`, so links are looked for outside code only. An opening run of backticks
// without a closing run of the same length before a blank line is literal text.
void extract_spans(const std::string& text, std::vector<Quote>& quotes, std::string& prose) {
  prose = text;
  std::size_t i = 0;
  while (i < text.size()) {
    if (text[i] != '`') {
      ++i;
      continue;
    }
    std::size_t run = 0;
    while (i + run < text.size() && text[i + run] == '`') ++run;
    const std::string fence(run, '`');
    std::size_t close = text.find(fence, i + run);
    while (close != std::string::npos && close + run < text.size() && text[close + run] == '`')
      close = text.find(fence, close + run + 1);  // a longer run does not close this span
    const std::size_t paragraph_end = text.find("\n\n", i);
    if (close == std::string::npos || (paragraph_end != std::string::npos && close > paragraph_end)) {
      i += run;
      continue;
    }
    std::string content = text.substr(i + run, close - i - run);
    for (char& c : content)
      if (c == '\n') c = ' ';
    if (content.size() >= 2 && content.front() == ' ' && content.back() == ' ')
      content = content.substr(1, content.size() - 2);
    Quote q;
    q.line = 1 + static_cast<int>(std::count(text.begin(), text.begin() + static_cast<long>(i), '\n'));
    q.text = content;
    quotes.push_back(q);
    for (std::size_t k = i; k < close + run; ++k)
      if (prose[k] != '\n') prose[k] = ' ';
    i = close + run;
  }
}

void extract_links(const std::string& prose, std::vector<Link>& links) {
  static const std::regex link_re(R"(!?\[[^\]\n]*\]\(([^()\s]+)(\s+"[^"]*")?\))");
  for (auto it = std::sregex_iterator(prose.begin(), prose.end(), link_re); it != std::sregex_iterator(); ++it) {
    Link link;
    link.line = 1 + static_cast<int>(std::count(prose.begin(), prose.begin() + it->position(0), '\n'));
    link.target = (*it)[1].str();
    links.push_back(link);
  }
}

}  // namespace

std::string github_anchor(const std::string& heading) {
  std::string anchor;
  for (const char c : heading) {
    const auto u = static_cast<unsigned char>(c);
    if (u >= 0x80 || std::isalnum(u) || c == '-' || c == '_')
      anchor += static_cast<char>(u < 0x80 ? std::tolower(u) : u);
    else if (c == ' ')
      anchor += '-';
  }
  return anchor;
}

MarkdownPage scan_markdown(const std::string& text) {
  MarkdownPage page;
  std::map<std::string, int> seen;  // GitHub numbers repeated headings: x, x-1, x-2
  std::string outside;              // the page with fenced lines blanked
  bool in_fence = false;
  bool shell = false;
  int number = 0;
  for (const std::string& line : split_lines(text)) {
    ++number;
    const std::string trimmed = trim(line);
    if (is_fence(trimmed)) {
      shell = !in_fence && is_shell_info(trimmed.substr(3));
      in_fence = !in_fence;
      outside += '\n';
      continue;
    }
    if (in_fence) {
      page.quotes.push_back(Quote{number, line, true, shell});
      outside += '\n';
      continue;
    }
    const std::string heading = heading_text(line);
    if (!heading.empty()) {
      const std::string anchor = github_anchor(heading);
      const int n = seen[anchor]++;
      page.anchors.push_back(n == 0 ? anchor : anchor + "-" + std::to_string(n));
    }
    outside += line + '\n';
  }
  std::string prose;
  extract_spans(outside, page.quotes, prose);
  extract_links(prose, page.links);
  return page;
}

std::vector<std::string> shell_words(const std::string& text) {
  std::vector<std::string> words;
  std::string word;
  bool have = false;
  char quote = 0;
  for (const char c : text) {
    if (quote != 0) {
      if (c == quote) quote = 0;
      else word += c;
    } else if (c == '\'' || c == '"') {
      quote = c;
      have = true;
    } else if (std::isspace(static_cast<unsigned char>(c))) {
      if (have) words.push_back(word);
      word.clear();
      have = false;
    } else {
      word += c;
      have = true;
    }
  }
  if (have) words.push_back(word);
  return words;
}

std::vector<std::vector<std::string>> shell_commands(const std::string& line) {
  std::string text = trim(line);
  if (text.rfind("$ ", 0) == 0) text = text.substr(2);
  std::vector<std::string> pieces(1);
  char quote = 0;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (quote != 0) {
      if (c == quote) quote = 0;
      pieces.back() += c;
    } else if (c == '\'' || c == '"') {
      quote = c;
      pieces.back() += c;
    } else if (c == '#' && (i == 0 || std::isspace(static_cast<unsigned char>(text[i - 1])))) {
      break;  // a comment
    } else if (c == '|' || c == '&' || c == ';' || c == '(' || c == ')') {
      pieces.emplace_back();
    } else {
      pieces.back() += c;
    }
  }
  std::vector<std::vector<std::string>> commands;
  for (const std::string& piece : pieces) {
    auto words = shell_words(piece);
    if (!words.empty()) commands.push_back(std::move(words));
  }
  return commands;
}

}  // namespace causal::docs
