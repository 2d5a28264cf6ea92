// The floor of the benchmark: reads a file in 1 MiB chunks and counts its
// lines and words (runs of non-blank bytes), like `wc -lw`. Any checker has to
// touch every byte at least this way.
//
//     wordscan FILE   ->  "<lines> <words> <bytes>"
#include <fcntl.h>
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <vector>

int main(int argc, char** argv) {
    if (argc != 2) {
        std::fprintf(stderr, "usage: wordscan FILE\n");
        return 2;
    }
    const int fd = ::open(argv[1], O_RDONLY);
    if (fd < 0) {
        std::perror(argv[1]);
        return 2;
    }
    std::vector<char> buf(size_t(1) << 20);
    uint64_t lines = 0, words = 0, bytes = 0;
    bool in_word = false;
    while (true) {
        const ssize_t n = ::read(fd, buf.data(), buf.size());
        if (n < 0) {
            std::perror(argv[1]);
            return 2;
        }
        if (n == 0) break;
        bytes += static_cast<uint64_t>(n);
        for (ssize_t i = 0; i < n; ++i) {
            const unsigned char c = static_cast<unsigned char>(buf[static_cast<size_t>(i)]);
            const bool blank = c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\f' || c == '\v';
            lines += c == '\n';
            words += !blank && !in_word;
            in_word = !blank;
        }
    }
    ::close(fd);
    std::printf("%llu %llu %llu\n", static_cast<unsigned long long>(lines), static_cast<unsigned long long>(words),
                static_cast<unsigned long long>(bytes));
    return 0;
}
