// Findings of files checked in parallel, handed on in the order of the files.
//
// `osplint check -j N` walks N files at once, but a report lists the files in
// order, each whole. The file whose turn it is writes straight through (under
// a lock); the others wait in a spool each (in memory up to a few megabytes,
// then in a temporary file), replayed when their turn comes. Memory stays
// bounded whatever the number of findings.
#pragma once

#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "osplint/diagnostic.h"
#include "support/io.h"

namespace osplint {

class OrderedOutput {
public:
    // `files` channels, handing on to `sink` in channel order.
    OrderedOutput(DiagnosticSink& sink, size_t files);
    ~OrderedOutput();
    // The sink for file `i` (used by one thread at a time).
    DiagnosticSink& channel(size_t i);
    // Where a spool could not be written (the findings of that file are lost).
    std::vector<std::string> errors() const;

private:
    class Channel;
    friend class Channel;
    // Called with `m_` held when channel `i` ends: the files after it that
    // are complete are replayed, the next one still running goes direct.
    void advance_locked();

    DiagnosticSink& sink_;
    std::vector<std::unique_ptr<Channel>> channels_;
    size_t current_ = 0;  // the channel whose turn it is
    mutable std::mutex m_;
    std::vector<std::string> errors_;
};

// The binary form of the sink calls a spool holds.
void encode_diagnostic(std::string& out, const Diagnostic& d);
bool decode_diagnostic(std::string_view& in, Diagnostic& d);

}  // namespace osplint
