// The docs test: what README.md and docs/ quote stays true. Paths exist, quoted tools are built and answer --help
// with the options quoted, scripts know their quoted options, links resolve. The checker itself is tested first on
// a small tree with known mistakes, so a checker that finds nothing cannot pass.
#include "docs_checks.hpp"
#include "markdown_quotes.hpp"
#include "test_files.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <fstream>
#include <functional>
#include <iostream>
#include <sstream>

namespace fs = std::filesystem;
using namespace causal::docs;

namespace {

const fs::path kSource = CAUSAL_TWIN_SOURCE_DIR;
const fs::path kBuild = CAUSAL_TWIN_BINARY_DIR;

using causal::test::slurp;

void write_text(const fs::path& path, const std::string& text, bool executable = false) {
  fs::create_directories(path.parent_path());
  std::ofstream(path) << text;
  if (executable) fs::permissions(path, fs::perms::owner_all, fs::perm_options::add);
}

const Repository& repository() {
  static const Repository repo = load_repository(kSource, kBuild, CAUSAL_TWIN_BENCHMARKS_BUILT != 0);
  return repo;
}

// Runs one check over every page, prints what was skipped, returns every problem.
CheckReport over_all_pages(const Repository& repo,
                           const std::function<CheckReport(const std::string&, const MarkdownPage&)>& check) {
  CheckReport all;
  for (const std::string& page : documentation_pages(repo.source)) {
    CheckReport one = check(page, scan_markdown(slurp(repo.source / page)));
    all.problems.insert(all.problems.end(), one.problems.begin(), one.problems.end());
    all.notes.insert(all.notes.end(), one.notes.begin(), one.notes.end());
    all.checked += one.checked;
  }
  for (const std::string& note : all.notes) std::cout << "skipped: " << note << "\n";
  return all;
}

// One check over every page of the repository: prints how many quotes it checked, which must be more than
// `more_than` (a scanner that finds nothing passes nothing), and expects no problem.
void expect_every_page_passes(const std::string& what, int more_than,
                              const std::function<CheckReport(const std::string&, const MarkdownPage&)>& check) {
  const CheckReport report = over_all_pages(repository(), check);
  std::cout << what << " checked: " << report.checked << "\n";
  EXPECT_GT(report.checked, more_than);
  EXPECT_TRUE(report.problems.empty()) << format(report.problems);
}

}  // namespace

TEST(DocsScanner, FindsSpansFencesLinksAndAnchors) {
  const MarkdownPage page = scan_markdown(
      "# Top\n\nRun `causal-ask --domain N\n--percent -10` and see [Many](install.md#many-hosts).\n"
      "## The operator's terminal, metrics\n```sh\ndeploy/launch.sh --features f.csv  # comment | not a pipe\n```\n"
      "```\n$ causal-ask --intervene 2\noutput [not](a-link.md)\n```\n`` a `tick` ``\n");
  ASSERT_EQ(page.anchors, (std::vector<std::string>{"top", "the-operators-terminal-metrics"}));
  ASSERT_EQ(page.links.size(), 1u);
  EXPECT_EQ(page.links[0].target, "install.md#many-hosts");
  EXPECT_EQ(page.links[0].line, 4);
  ASSERT_EQ(page.quotes.size(), 5u);  // three fenced lines, two spans
  EXPECT_TRUE(page.quotes[0].shell_fence);
  EXPECT_FALSE(page.quotes[1].shell_fence);
  EXPECT_EQ(page.quotes[3].text, "causal-ask --domain N --percent -10");
  EXPECT_EQ(page.quotes[3].line, 3);
  EXPECT_EQ(page.quotes[4].text, "a `tick`");
  const auto commands = shell_commands("(cd build && cpack -G DEB) | x 'a|b'  # c");
  ASSERT_EQ(commands.size(), 3u);
  EXPECT_EQ(commands[1], (std::vector<std::string>{"cpack", "-G", "DEB"}));
  EXPECT_EQ(commands[2], (std::vector<std::string>{"x", "a|b"}));
}

TEST(DocsChecks, ReportMissingPathsToolsOptionsAndLinks) {
  const fs::path root = fs::temp_directory_path() / ("docs_check_" + std::to_string(::getpid()));
  fs::remove_all(root);
  write_text(root / "deploy/run.sh", "case $1 in --known) ;; esac\n", true);
  write_text(root / "common/x/include/a.hpp", "");
  write_text(root / "build/CMakeCache.txt", "");
  write_text(root / "build/services/causal-fake", "#!/bin/sh\n[ \"$1\" = --version ] && exit 3\necho 'usage: causal-fake --known'\n",
             true);
  write_text(root / "docs/other.md", "# Other\n## Real heading\n");
  write_text(root / "README.md",
             "`deploy/run.sh --known`, `deploy/gone.sh`, `common/x/.../a.hpp`, `a.hpp`, `missing.hpp`, `DIR/x.xml`\n\n"
             "```sh\ndeploy/run.sh --unknown\ncausal-fake --known --wrong\ncausal-absent --help\nls /nowhere\n```\n"
             "[ok](docs/other.md#real-heading) [bad](docs/none.md) [anchor](docs/other.md#nope) "
             "[later](docs/advice.md) [self](#nothing)\n");
  const Repository repo = load_repository(root, root / "build", false);
  HelpCache help;
  const MarkdownPage page = scan_markdown(slurp(root / "README.md"));
  const std::string paths = format(check_paths(repo, "README.md", page).problems);
  const std::string commands = format(check_commands(repo, "README.md", page, help).problems);
  const CheckReport links = check_links(repo, "README.md", page);
  fs::remove_all(root);

  EXPECT_NE(paths.find("'deploy/gone.sh' does not exist"), std::string::npos) << paths;
  EXPECT_NE(paths.find("'missing.hpp' is in no folder"), std::string::npos) << paths;
  EXPECT_EQ(std::count(paths.begin(), paths.end(), '\n'), 2) << paths;  // a.hpp (twice) and DIR/x.xml pass
  EXPECT_NE(commands.find("'deploy/run.sh' does not know the quoted option --unknown"), std::string::npos) << commands;
  EXPECT_NE(commands.find("list the quoted option --wrong"), std::string::npos) << commands;
  EXPECT_NE(commands.find("'causal-absent' is not an executable"), std::string::npos) << commands;
  EXPECT_NE(commands.find("'causal-fake --version' did not exit 0"), std::string::npos) << commands;
  EXPECT_EQ(std::count(commands.begin(), commands.end(), '\n'), 4) << commands;
  const std::string link_text = format(links.problems);
  EXPECT_NE(link_text.find("docs/none.md does not exist"), std::string::npos) << link_text;
  EXPECT_NE(link_text.find("no heading #nope"), std::string::npos) << link_text;
  EXPECT_NE(link_text.find("no heading #nothing"), std::string::npos) << link_text;
  EXPECT_EQ(links.problems.size(), 3u) << link_text;
  ASSERT_EQ(links.notes.size(), 1u);  // docs/advice.md: expected after the merge
  EXPECT_NE(links.notes[0].find("docs/advice.md"), std::string::npos);
}

TEST(Docs, ReadmeIsTheFrontDoorWithTheTwoSetUpCommands) {
  const std::string readme = slurp(kSource / "README.md");
  const auto lines = std::count(readme.begin(), readme.end(), '\n');
  EXPECT_LE(lines, 200) << "README.md is the front door; move detail to docs/";
  bool demo = false;
  bool test = false;
  for (const Quote& q : scan_markdown(readme).quotes) {
    if (!q.shell_fence) continue;
    for (const auto& command : shell_commands(q.text)) {
      demo = demo || command == std::vector<std::string>{"./deploy/demo.sh"};
      test = test || command == std::vector<std::string>{"./deploy/test.sh"};
    }
  }
  EXPECT_TRUE(demo) << "README.md must state ./deploy/demo.sh in a sh block";
  EXPECT_TRUE(test) << "README.md must state ./deploy/test.sh in a sh block";
}

TEST(Docs, QuotedRepositoryPathsExist) {
  const Repository& repo = repository();
  expect_every_page_passes("paths", 100,
                           [&](const std::string& page, const MarkdownPage& m) { return check_paths(repo, page, m); });
}

TEST(Docs, QuotedToolsAreBuiltAndAnswerHelpWithTheirOptions) {
  const Repository& repo = repository();
  HelpCache help;
  expect_every_page_passes(
      "commands", 30, [&](const std::string& page, const MarkdownPage& m) { return check_commands(repo, page, m, help); });
}

TEST(Docs, LinksBetweenPagesResolve) {
  const Repository& repo = repository();
  expect_every_page_passes("links", 20,
                           [&](const std::string& page, const MarkdownPage& m) { return check_links(repo, page, m); });
  for (const std::string& page : pages_expected_after_merge())
    if (!fs::exists(kSource / page)) std::cout << "expected after the merge, not here yet: " << page << "\n";
}
