#include "io/animation_choice.h"

#include <algorithm>

namespace sweepd::io {

namespace {

std::string animation_list(std::span<const std::string> names) {
  std::string list;
  for (std::size_t a = 0; a < names.size(); ++a)
    list += (a ? ", " : "") + std::to_string(a) + " '" + names[a] + "'";
  return list;
}

}  // namespace

int choose_animation(std::span<const std::string> names, const std::string& clip,
                     const std::filesystem::path& file) {
  if (names.empty()) throw LoadError(file, "the file has no animations (no clip '" + clip + "')");
  for (std::size_t a = 0; a < names.size(); ++a)
    if (names[a] == clip) return static_cast<int>(a);
  const bool digits =
      !clip.empty() && clip.size() < 10 &&
      std::all_of(clip.begin(), clip.end(), [](char c) { return c >= '0' && c <= '9'; });
  if (!digits)
    throw LoadError(file, "no animation named '" + clip +
                              "' (the file's animations: " + animation_list(names) + ")");
  const int index = std::stoi(clip);
  if (index >= static_cast<int>(names.size()))
    throw LoadError(file, "no animation " + clip + ": the file has " +
                              std::to_string(names.size()) + " (" + animation_list(names) + ")");
  return index;
}

std::vector<FileAnimation> every_animation(std::span<const std::string> names,
                                           const std::function<motion::Clip(int index)>& read) {
  std::vector<FileAnimation> all;
  for (std::size_t a = 0; a < names.size(); ++a) {
    FileAnimation& animation = all.emplace_back();
    animation.name = names[a];
    try {
      animation.clip = read(static_cast<int>(a));
    } catch (const LoadError& error) {
      animation.error = error.what();
    }
  }
  return all;
}

}  // namespace sweepd::io
