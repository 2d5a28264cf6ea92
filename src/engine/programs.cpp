#include "engine/programs.h"

#include <fstream>
#include <iterator>

namespace osplint {

bool is_subprogram_file(const std::filesystem::path& p) {
    std::string ext = p.extension().string();
    for (auto& c : ext) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    return ext == ".SSB" || ext == ".SUB" || ext == ".LIB" || ext == ".MSB";
}

void collect_directory_program_names(const std::filesystem::path& dir, ProgramNames& out) {
    std::error_code ec;
    for (std::filesystem::directory_iterator it(dir.empty() ? "." : dir, ec), end; !ec && it != end; it.increment(ec)) {
        std::error_code e2;
        if (!is_subprogram_file(it->path()) || !it->is_regular_file(e2)) continue;
        if (it->file_size(e2) > (64u << 20)) continue;  // not a subprogram library
        std::ifstream in(it->path(), std::ios::binary);
        std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        collect_program_names(text, out);
    }
}

}  // namespace osplint
