// What the files of the macro catalog share (catalog.h is the public
// interface):
//
//   catalog.cpp        lookups, the names of the enumerations, the catalog's
//                      expressions, the shipped catalog
//   catalog_read.cpp   reading catalog tables (the shipped file, a
//                      configuration's [macro] tables) into specs, with
//                      line-accurate errors; validation; merging
//   catalog_card.cpp   a macro's card (`osplint explain`, hover)
#pragma once

#include <optional>
#include <string>
#include <string_view>

#include "catalog/catalog.h"
#include "support/text.h"

namespace osplint::catalog_detail {

// ---------------------------------------------------------------------------
// Small string helpers

using osplint::iequals;  // support/text.h
using osplint::upper;
std::string format_number(double v);
// The whole of `s` as a number ("5", "-0.5", "1000"), else nullopt.
std::optional<double> parse_number(std::string_view s);
// "g0114" -> "G114"; "M204" -> "M204"; empty on a malformed code.
std::string normalize_code(std::string_view code);
// Letters and digits only, at least one.
bool is_name(std::string_view s);

// ---------------------------------------------------------------------------
// Enumerations and their names in the files

template <class E>
struct EnumName {
    std::string_view name;
    E value;
};

inline constexpr EnumName<ArgOmitted> kOmitted[] = {
    {"required", ArgOmitted::Required}, {"default", ArgOmitted::Default},
    {"current", ArgOmitted::Current},   {"none", ArgOmitted::None},
    {"unknown", ArgOmitted::Unknown},
};
inline constexpr EnumName<ArgSign> kSign[] = {
    {"any", ArgSign::Any},
    {"positive", ArgSign::Positive},
    {"non-negative", ArgSign::NonNegative},
    {"non-zero", ArgSign::NonZero},
};
inline constexpr EnumName<ArgRole> kRole[] = {
    {"position", ArgRole::Position}, {"cycle", ArgRole::Cycle},
    {"length", ArgRole::Length},     {"stroke", ArgRole::Stroke},
    {"shift", ArgRole::Shift},       {"feed", ArgRole::Feed},
    {"speed", ArgRole::Speed},       {"dwell", ArgRole::Dwell},
    {"time", ArgRole::Time},         {"comp-number", ArgRole::CompNumber},
    {"m-code", ArgRole::MCode},      {"vector", ArgRole::Vector},
    {"pitch", ArgRole::Pitch},       {"direction", ArgRole::Direction},
    {"count", ArgRole::Count},
};
inline constexpr EnumName<ArgInFormat> kInFormat[] = {
    {"required", ArgInFormat::Required},
    {"optional", ArgInFormat::Optional},
    {"absent", ArgInFormat::Absent},
};
inline constexpr EnumName<MacroForm> kForm[] = {
    {"CALL", MacroForm::Call},
    {"MODIN", MacroForm::Modin},
    {"GCODE", MacroForm::GCode},
    {"MCODE", MacroForm::MCode},
};
inline constexpr EnumName<M52Mode> kM52[] = {
    {"ignored-use-PM52", M52Mode::IgnoredUsePM52},
    {"fixed-cycle", M52Mode::FixedCycle},
    {"undocumented", M52Mode::Undocumented},
};
inline constexpr EnumName<M53Mode> kM53[] = {
    {"return-to-PT", M53Mode::ReturnToPT},
    {"fixed-cycle", M53Mode::FixedCycle},
    {"undocumented", M53Mode::Undocumented},
};
inline constexpr EnumName<RequiredScope> kScope[] = {
    {"every-call", RequiredScope::EveryCall},
    {"cycle-start", RequiredScope::CycleStart},
};

inline constexpr EnumName<MacroUnits> kUnits[] = {
    {"any", MacroUnits::Any},
    {"mm", MacroUnits::MmOnly},
};
inline constexpr EnumName<G91Mode> kG91[] = {
    {"follows-g91", G91Mode::FollowsG91},
    {"cycle-axis-absolute", G91Mode::CycleAxisAbsolute},
    {"unsupported", G91Mode::Unsupported},
};
inline constexpr EnumName<Hazard> kHazard[] = {
    {"g60-ncyl-collision", Hazard::G60NcylCollision},
    {"overwrites-vc120-vc128", Hazard::OverwritesVc120To128},
    {"repeat-count-abnormal", Hazard::RepeatCountAbnormal},
};

// The name of `v` in the files.
template <class E, std::size_t N>
std::string_view name_in(const EnumName<E> (&table)[N], E v) {
    for (const auto& e : table)
        if (e.value == v) return e.name;
    return "?";
}

// The names of a table, quoted and separated by commas (for messages).
template <class E, std::size_t N>
std::string choices(const EnumName<E> (&table)[N]) {
    std::string s;
    for (const auto& e : table) {
        if (!s.empty()) s += ", ";
        s += '"';
        s += e.name;
        s += '"';
    }
    return s;
}

}  // namespace osplint::catalog_detail
