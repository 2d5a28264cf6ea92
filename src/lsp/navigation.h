// Language server: names and where they are written. Sequence names (`N100`,
// `NSKIP`) are local to their program: defined at the start of a block, jumped
// to by GOTO and IF. Program names (`OSUB`) are defined at the start of a
// program and called by CALL and MODIN, from the document, the other open
// documents and the subprogram files beside it.
//
// The blocks that jump are those of the outline (syntax/outline.h); a line is
// parsed only when it may hold what is looked for (a sequence name starts its
// block with an N; a call holds CALL or MODIN), with the same front end as the
// analysis.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "lsp/document.h"
#include "lsp/text.h"
#include "syntax/frontend_fast.h"

namespace osplint::lsp {

// A document other than the one asked about: open in the editor (as last
// analysed) or read from disk (a subprogram file beside it).
struct OtherDocument {
    std::string uri;
    const DocumentModel* doc = nullptr;
};

// A document read from disk (a subprogram file) or copied from the editor's
// text (another open document), with its outline (program names only).
struct DiskDocument {
    std::string uri;
    DocumentModel doc;
};
DiskDocument outlined_document(std::string uri, std::string path, std::string text);
// The file at `p`, read and outlined so (nullopt: it cannot be read).
std::optional<DiskDocument> read_outlined_document(const std::filesystem::path& p);

// The subprogram files (.SSB .SUB .LIB .MSB, any case) of `dir`, except the
// paths in `skip` (open documents) and files over 64 MiB.
std::vector<DiskDocument> sibling_documents(const std::filesystem::path& dir, const std::set<std::string>& skip);

// What the position names.
struct NameAt {
    enum Kind { None, Sequence, Program } kind = None;
    std::string name;        // upper case, with its letter: "N100", "OSUB"
    ByteRange range;         // the name as written at the position
    size_t program = 0;      // Sequence: the program it belongs to
    bool definition = false; // the position is on a definition
};
NameAt name_at(const DocumentModel& doc, uint32_t offset);

// Where a name is written.
struct NameSite {
    ByteRange range;
    bool definition = false;
};
// The definitions of sequence name `name` in program `program` and the jumps
// (GOTO, IF) to it, in text order.
std::vector<NameSite> sequence_sites(const DocumentModel& doc, size_t program, std::string_view name);
// The definitions of program `name` in the document and its CALL/MODIN sites, in text order.
std::vector<NameSite> program_sites(const DocumentModel& doc, std::string_view name);

// The sequence names a program defines: the name, its range, the block's range.
struct SequenceDefinition {
    std::string name;
    ByteRange range;
    ByteRange block;
};
std::vector<SequenceDefinition> sequence_definitions(const DocumentModel& doc, size_t program, size_t limit = SIZE_MAX);

// The 1-based line range [first, last] of program `i`.
std::pair<uint32_t, uint32_t> program_lines(const DocumentModel& doc, size_t i);
// The program holding a 1-based line.
size_t program_of_line(const FileOutline& outline, uint32_t line);
// Parses one line of `src` (1-based) into `out`.
void parse_source_line(const SourceText& src, uint32_t line, FastLineParser& parser, Block& out);
// The 1-based lines of [first, last] that hold `word` (upper case) in any case.
std::vector<uint32_t> lines_holding(const SourceText& src, uint32_t first, uint32_t last, std::string_view word);

// Whether `name` can be written as a sequence name: it parses as the name of a
// block and as the target of a GOTO (so `NCYL`, `N`, `N-1`, `NA B` cannot).
bool valid_sequence_name(std::string_view name);

// --- requests ---------------------------------------------------------------
// `others` are searched for program definitions and calls after the document.
json definition(const DocumentModel& doc, const std::string& uri, uint32_t offset,
                const std::vector<OtherDocument>& others, Encoding enc);
json references(const DocumentModel& doc, const std::string& uri, uint32_t offset, bool include_declaration,
                const std::vector<OtherDocument>& others, Encoding enc);
json document_highlight(const DocumentModel& doc, uint32_t offset, Encoding enc);
// Null when the position is not on a sequence name.
json prepare_rename(const DocumentModel& doc, uint32_t offset, Encoding enc);
// Throws std::invalid_argument for a position that is not on a sequence name,
// a new name that is not a sequence name, or one the program already defines.
json rename(const DocumentModel& doc, const std::string& uri, uint32_t offset, std::string_view new_name,
            Encoding enc);

}  // namespace osplint::lsp
