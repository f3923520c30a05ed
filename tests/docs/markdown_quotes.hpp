// What a Markdown page quotes: code spans, fenced code lines, links and heading anchors. The docs test checks
// these (paths exist, tools answer --help, links resolve) and never the prose around them, so rewording a page
// cannot fail it.
#pragma once

#include <string>
#include <vector>

namespace causal::docs {

// One piece of quoted code: an inline `code span` (may run over a line break) or one line of a fenced block.
struct Quote {
  int line = 0;             // 1-based line where it starts
  std::string text;         // without the backticks / fence
  bool in_fence = false;    // a line of a fenced block
  bool shell_fence = false; // that block is marked sh, bash, shell or console
};

// A Markdown link or image target, [text](target) or ![alt](target), outside code.
struct Link {
  int line = 0;
  std::string target;
};

struct MarkdownPage {
  std::vector<Quote> quotes;
  std::vector<Link> links;
  std::vector<std::string> anchors; // GitHub anchors of the page's headings ("## Many hosts" -> "many-hosts")
};

// Splits a page into quotes, links and anchors.
MarkdownPage scan_markdown(const std::string& text);

// GitHub's anchor for a heading's text: lower case, punctuation other than '-' and '_' removed, spaces -> '-'.
std::string github_anchor(const std::string& heading);

// Whitespace-separated words, with quotes ('...', "...") kept inside one word.
std::vector<std::string> shell_words(const std::string& text);

// The commands of a shell line: split at |, &&, ||, ;, ( and ) outside quotes, a trailing # comment removed,
// a leading "$ " prompt removed. Each command is its words.
std::vector<std::vector<std::string>> shell_commands(const std::string& line);

}  // namespace causal::docs
