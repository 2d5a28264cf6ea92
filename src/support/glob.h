// Glob patterns of paths, as `exclude` and `[[per-path]]` of osplint.toml and
// `--exclude` write them:
//
//     *        any run of characters within one path component (not '/')
//     ?        one character other than '/'
//     [abc]    one character of the set; [a-z] a range; [!abc] or [^abc] not in the set
//     **       as a whole component: any number of components, none included
//              ("old/**" is everything under old, "**/x.MIN" is x.MIN anywhere)
//
// Paths use '/' between components. Matching is byte by byte and case
// sensitive, like the file systems the programs are kept on.
#pragma once

#include <string_view>

namespace osplint {

// Whether the whole of `path` matches `pattern`.
bool glob_match(std::string_view pattern, std::string_view path);

// Whether `pattern` is well formed (every '[' closed); the reason when it is not.
bool glob_valid(std::string_view pattern, std::string_view* why = nullptr);

}  // namespace osplint
