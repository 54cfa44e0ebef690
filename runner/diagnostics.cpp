// Compiler-style diagnostics for study files, edit distance and did-you-mean suggestions.
#include "diagnostics.hpp"

#include <algorithm>

namespace sph::runner {

std::string format_diagnostic(const Diagnostic& d) {
  std::string s = d.file;
  if (d.line > 0) {
    s.append(":").append(std::to_string(d.line));
    if (d.column > 0)
      s.append(":").append(std::to_string(d.column));
  }
  return s.append(": error: ").append(d.message);
}

namespace {
std::string join_diagnostics(const std::vector<Diagnostic>& ds) {
  std::string s;
  for (const auto& d : ds) {
    if (!s.empty())
      s += "\n";
    s += format_diagnostic(d);
  }
  return s;
}
} // namespace

StudyError::StudyError(std::vector<Diagnostic> diagnostics)
    : std::runtime_error(join_diagnostics(diagnostics)), diagnostics_(std::move(diagnostics)) {}

void Diagnostics::error(int line, std::string message, int column) {
  items_.push_back({file_, line, column, std::move(message)});
}

void Diagnostics::throw_if_any() const {
  if (items_.empty())
    return;
  auto sorted = items_;
  std::stable_sort(sorted.begin(), sorted.end(),
                   [](const Diagnostic& a, const Diagnostic& b) { return a.line < b.line; });
  constexpr std::size_t max_reported = 25;
  if (sorted.size() > max_reported) {
    auto more = sorted.size() - max_reported;
    sorted.resize(max_reported);
    sorted.push_back({file_, 0, 0, std::to_string(more) + " more errors not shown"});
  }
  throw StudyError(std::move(sorted));
}

std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> prev(b.size() + 1), cur(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j)
    prev[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    cur[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      std::size_t subst = prev[j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1);
      cur[j] = std::min({prev[j] + 1, cur[j - 1] + 1, subst});
    }
    std::swap(prev, cur);
  }
  return prev[b.size()];
}

std::string did_you_mean(const std::string& word, const std::vector<std::string>& candidates) {
  const std::string* best = nullptr;
  std::size_t best_d = 0;
  for (const auto& c : candidates) {
    auto d = edit_distance(word, c);
    if (!best || d < best_d)
      best = &c, best_d = d;
  }
  std::size_t limit = std::max<std::size_t>(2, word.size() / 3);
  if (best && best_d <= limit)
    return " (did you mean '" + *best + "'?)";
  return "";
}

std::string quoted_list(const std::vector<std::string>& items) {
  std::string s;
  for (const auto& i : items) {
    if (!s.empty())
      s += ", ";
    s += "'" + i + "'";
  }
  return s;
}

} // namespace sph::runner
