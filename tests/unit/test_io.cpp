// Reading input (support/io.h): a line longer than kMaxLineLength stops the
// reading with a message naming the line, in the line stream, the outline,
// the copy of standard input and a whole check; memory never grows with it.
#include <doctest/doctest.h>

#include <signal.h>
#include <unistd.h>

#include <string>
#include <thread>

#include "api/check.h"
#include "support/io.h"
#include "syntax/outline.h"

using namespace osplint;

TEST_CASE("a line longer than kMaxLineLength stops the line stream") {
    for (size_t chunk : {size_t(7), size_t(64) << 10, size_t(4) << 20}) {
        const std::string ok_line(kMaxLineLength, 'X');
        const std::string text = "G0\r\n" + ok_line + "\n" + std::string(kMaxLineLength + 1, 'Y') + "\nG1\n";
        MemorySource src(text);
        LineStream ls(src, chunk);
        LineRef l;
        REQUIRE(ls.next(l));
        REQUIRE(ls.next(l));
        CHECK(l.text.size() == kMaxLineLength);
        CHECK_FALSE(ls.next(l));
        CHECK(ls.error());
        CHECK(ls.stop_reason() == line_too_long_message(3));
    }
}

TEST_CASE("a line longer than kMaxLineLength is an input error of the outline and of the check") {
    const std::string text = "O1\nG0\n" + std::string(3 * kMaxLineLength, '\0');
    MemorySource src(text);
    const FileOutline o = outline_file(src);
    CHECK(o.error == line_too_long_message(3));
    const FileResult r = check_text("LONG.MIN", text, Config{});
    CHECK(r.io_error == line_too_long_message(3));
    CHECK(line_too_long_message(3).find("line 3 is longer than") == 0);
}

TEST_CASE("the copy of standard input stops at a line longer than kMaxLineLength") {
    ::signal(SIGPIPE, SIG_IGN);  // the writer finds the pipe closed
    int fds[2];
    REQUIRE(::pipe(fds) == 0);
    // Lines end with LF, CRLF and a lone CR (the CR of a CRLF at the end of a read too).
    std::thread writer([w = fds[1]] {
        const std::string head = "A\r\nB\rC\n";
        (void)!::write(w, head.data(), head.size());
        const std::string zeros(64 << 10, '\0');
        for (size_t sent = 0; sent < 4 * kMaxLineLength; sent += zeros.size())
            if (::write(w, zeros.data(), zeros.size()) < 0) break;
        ::close(w);
    });
    std::string error;
    const int fd = spool_to_temporary_file(fds[0], error);
    ::close(fds[0]);  // the writer then fails, and ends
    writer.join();
    CHECK(fd < 0);
    CHECK(error == line_too_long_message(4));
}
