// The macro catalog: the shop library's custom cycle macros and the control's
// fixed cycles, as data.
//
// The argument tables, call forms, mode behaviour, action sequences and the
// readings taken where the manuals contradict themselves live in
// data/macros.toml (embedded in the binary). Shops add or adjust macros in
// their osplint.toml with the same schema (`[macro.NAME]` tables, see
// docs/catalog.md); `Catalog::merge` applies them. Rules ask the catalog; they
// never hard-code a macro's table.
//
// Pointers returned by the lookups stay valid for the catalog's lifetime,
// also across `merge` (a replaced macro is updated in place).
#pragma once

#include <array>
#include <cstdint>
#include <deque>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "catalog/condition.h"

namespace toml {
inline namespace v3 {
class table;
}
}  // namespace toml

namespace osplint {

// What happens when an argument is left out (the manuals' 省略時の処理 column,
// after the readings in the catalog are applied).
enum class ArgOmitted : uint8_t {
    Required,  // エラー: omitting it raises an alarm
    Default,   // a printed default value or expression (`default_text`)
    Current,   // 現在値: the current modal value or position is used
    None,      // 無し: no value; the related function is not performed
    Unknown,   // the manual does not say (undocumented or table-less arguments)
};

enum class ArgSign : uint8_t { Any, Positive, NonNegative, NonZero };

enum class ArgRole : uint8_t {
    Position,    // positioning-plane coordinate (follows G90/G91)
    Cycle,       // cycle-axis coordinate
    Length,      // a length or distance (not a coordinate)
    Stroke,      // a tool or clutch stroke
    Shift,       // a shift for tool insertion/withdrawal or relief
    Feed,        // a feed rate
    Speed,       // spindle speed
    Dwell,       // dwell time
    Time,        // another time (e.g. intermittent lubrication)
    CompNumber,  // cutter-radius compensation number
    MCode,       // M code handed over to the macro (PM=52)
    Vector,      // end-point vector component
    Pitch,       // pitch
    Direction,   // a direction selector (G2/G3)
    Count,       // repeat count
};

// Whether an argument appears on a printed command-format line.
enum class ArgInFormat : uint8_t { Required, Optional, Absent };

// How a macro is invoked.
enum class MacroForm : uint8_t { Call, Modin, GCode, MCode };
inline constexpr std::size_t kMacroFormCount = 4;

// M52 written on the invoking line.
enum class M52Mode : uint8_t {
    IgnoredUsePM52,  // not read by the subprogram; command PM=52 (M52 on blocks
                     // executed while a MODIN call is modal is valid)
    FixedCycle,      // as with fixed cycles
    Undocumented,
};

enum class M53Mode : uint8_t {
    ReturnToPT,    // M53 returns to PT; G71 is not read; M53 without PT -> alarm
    FixedCycle,    // as with fixed cycles: G71 gives the return level
    Undocumented,  // the manual gives no M53 behaviour
};

enum class SpecKind : uint8_t { Macro, FixedCycle };

// The unit systems a macro can be used in (`units`).
enum class MacroUnits : uint8_t {
    Any,     // the manual states no restriction
    MmOnly,  // only the mm unit system
};

// What a macro does in G91 mode (`g91`).
enum class G91Mode : uint8_t {
    FollowsG91,         // as a fixed cycle: R relative to I, Z relative to R (OG84L)
    CycleAxisAbsolute,  // cycle-axis arguments from the workpiece origin even in G91;
                        // the positioning plane follows G90/G91 (the subprogram macros)
    Unsupported,        // not usable in G91: wrong motion, no alarm (OKYLX/OKYLY)
};

// What goes wrong with the macro beyond its arguments (`hazards`): facts of
// the macro that the rules read, not switches of the rules.
enum class Hazard : uint8_t {
    G60NcylCollision,     // G60 modal with NCYL while it is in use: NCYL is ignored, collision
    OverwritesVc120To128, // it writes the common variables VC120-VC128
    RepeatCountAbnormal,  // a repeat count Q on the call line: abnormal from the 2nd call
};
inline constexpr std::size_t kHazardCount = 3;

// Where a "required" argument has to be written.
enum class RequiredScope : uint8_t {
    EveryCall,   // on every CALL/MODIN/G-code line that invokes the macro
    CycleStart,  // on the block that starts the cycle; later blocks of the same
                 // cycle inherit the modal values (fixed cycles, G114)
};

struct ArgSpec {
    std::string name;                  // "PZ" (macros) or the address "Z" (fixed cycles, OG84L)
    std::vector<std::string> aliases;  // other names the manual uses for it ("PZ" for OG84L's Z)
    std::string meaning;
    ArgOmitted omitted = ArgOmitted::None;
    std::string default_text;            // the omitted column as printed (English), e.g. "PF*4"
    std::optional<double> default_value;  // when the default is a number
    ArgSign sign = ArgSign::Any;
    std::vector<double> allowed;  // when only these values are allowed (PG: 2, 3)
    bool negative_allowed = false;  // 負数可 printed
    ArgRole role = ArgRole::Length;
    std::array<char, 3> axes{};  // machine axis in G17, G18, G19; '\0' = none
    std::array<ArgInFormat, kMacroFormCount> in_format{ArgInFormat::Absent, ArgInFormat::Absent,
                                                       ArgInFormat::Absent, ArgInFormat::Absent};
    bool undocumented = false;        // referenced by the manual but not defined in its table
    bool always_incremental = false;  // incremental even under G90
    bool g91_only = false;            // valid only in G91 mode
    std::string source;               // "000:L153"
    std::string note;

    bool required() const { return omitted == ArgOmitted::Required; }
    // The machine axis this argument maps to in plane 17, 18 or 19, if any.
    std::optional<char> axis(int plane) const;
    ArgInFormat format_status(MacroForm form) const {
        return in_format[static_cast<std::size_t>(form)];
    }
};

struct FormatLine {
    MacroForm form = MacroForm::Call;
    std::string text;  // as printed, English-normalised ASCII
    std::string source;
};

// The G-code macro form (`G11* Xx Yy ...`): bare addresses mapped to arguments.
struct GCodeForm {
    std::string text;
    std::string source;
    std::map<std::string, std::string, std::less<>> address_map;  // "Q" -> "PQ"
    std::string note;
};

// At least one of `args` must be given (in `plane` when set: 17, 18, 19; 0 = any).
struct AtLeastOne {
    int plane = 0;
    std::vector<std::string> args;
    std::string source;
    bool inferred = false;
};

// The expressions of `ActionStep::target`, `ActionStep::by` and `Relation`:
// a sum of terms, each a number or an argument name, joined by + and -.
struct ExprTerm {
    int sign = 1;      // +1 or -1
    std::string name;  // argument name, empty for a number
    double number = 0;
};

// A relation between argument values: `left op right`, where both sides are
// simple expressions over argument names and numbers (see parse_catalog_expr).
struct Relation {
    std::string left, op, right;  // op: > >= < <= == !=
    int plane = 0;                // holds in this plane only (0 = any)
    Condition when;               // extra condition, e.g. given:PK
    std::string source;
    bool inferred = false;
    std::string note;
};

// A relation's sides as the rules read them at every call: parsed, and each
// term's argument found (its index in the spec's `args`, -1 for a number or a
// name that is no argument of the spec).
struct RelationSides {
    std::optional<std::vector<ExprTerm>> left, right;  // nullopt: not in the syntax
    std::vector<int> left_args, right_args;             // one per term
    // A side names a cycle-axis argument (PR > PZ): the relation orders
    // points on the cycle axis (OSP302's; the others, FA > F, are OSP103's).
    bool cycle_order = false;
};

// One step of the manual's action sequence. `target` is the cycle-axis
// position reached by the step, `by` a cycle-axis move of stated length but
// unstated direction. Both use the expression syntax: argument names, numbers,
// `+` and `-`.
struct ActionStep {
    std::string step;  // "3", "3a"
    std::string text;
    std::string feed;
    std::string target;
    std::string by;
    Condition when;  // M53, given:PK, G17 and (PM=52 or M52) ...
    bool inferred = false;
    std::string source;
};

// A step's `target` and `by` as the envelope reads them at every call: parsed,
// and each term's argument found (as RelationSides).
struct StepSides {
    std::optional<std::vector<ExprTerm>> target, by;  // nullopt: empty, or not in the syntax
    std::vector<int> target_args, by_args;            // one per term
    bool to_limit = false;  // neither: the step's text says it goes to the + travel limit
};

struct CatalogNote {
    std::string text;
    std::string source;
};

// A situation the manual warns about at the call, beyond the arguments'
// values (OSP116): "PFA omitted: its default is printed as FA/2", "the
// spindle turns in M4 at the call". `when` holds where it applies; `info`
// cautions describe a legitimate use worth knowing, the others a likely mistake.
struct Caution {
    std::string id;  // a key ("pfa-default"), for the configuration; not shown in messages
    Condition when;
    std::string text;
    std::string source;
    bool info = false;
};

// Where the manuals contradict themselves: what they disagree on, what is
// taken and why. `open` readings can be changed in the configuration.
struct Reading {
    std::string id;  // a key of the reading ("okylx-format"), never shown to users
    std::string issue;
    std::string reading;
    bool open = false;
    std::string override_hint;  // a config snippet that takes the other reading
};

struct MacroSpec {
    SpecKind kind = SpecKind::Macro;
    std::string name;  // "OZAGR"; fixed cycles: "G81"
    int gcode = 0;     // fixed cycles: 81
    std::string family;
    std::string title;
    std::string manual;  // a key of catalog/citations.h ("back-counterboring"), or a shop's own text
    std::string source;  // "000:L552-648"
    std::vector<MacroForm> forms;
    bool args_documented = true;  // false: argument table unknown (accept any)
    MacroUnits units = MacroUnits::Any;
    G91Mode g91 = G91Mode::FollowsG91;
    M52Mode m52 = M52Mode::Undocumented;
    M53Mode m53 = M53Mode::Undocumented;
    std::array<bool, kHazardCount> hazards{};  // indexed by Hazard
    bool tapping = false;
    RequiredScope required_scope = RequiredScope::EveryCall;
    std::vector<FormatLine> formats;
    std::optional<GCodeForm> gcode_form;
    std::vector<std::string> codes;  // G/M codes it is registered to by default ("G114")
    std::string cancel;   // the macro that cancels this one ("OC84L")
    std::string cancels;  // the macro this one cancels
    std::string plane_table;  // id of the manual's plane table
    std::string common;       // id of the manual's common rules
    std::vector<ArgSpec> args;  // in manual order
    std::vector<AtLeastOne> at_least_one;
    std::vector<Relation> relations;
    std::vector<ActionStep> action;
    std::vector<CatalogNote> notes;
    std::vector<Caution> cautions;
    std::vector<Reading> readings;
    std::string origin;  // the file that defined it last
    // `args` by name, then by alias, each packed upper-case into a number,
    // in an open-addressed table of a power-of-two size (key 0: a free slot;
    // a name met twice keeps its first argument), made by index_args when the
    // catalog is read: arg() runs for every argument of every call. Empty, or
    // made for another number of arguments: arg() compares the names.
    std::vector<std::pair<uint64_t, uint16_t>> arg_index;
    size_t arg_index_of = 0;  // args.size() when it was made
    // Makes arg_index, relation_sides_, step_sides_ and action_args_.
    void index_args();
    void index_action_args();  // the part of index_args that makes action_args_
    // `relations` with their sides read (relation_sides), made with
    // index_args; for another number of relations, sides() makes none.
    std::vector<RelationSides> relation_sides_;
    size_t relation_sides_of = 0;    // relations.size() when they were made
    size_t relation_sides_args_ = 0; // args.size() then
    // The sides of relation `i`, or nullptr when they were not made (then
    // relation_sides reads them).
    const RelationSides* sides(size_t i) const {
        return relation_sides_of == relations.size() && relation_sides_args_ == args.size() &&
                       i < relation_sides_.size()
                   ? &relation_sides_[i]
                   : nullptr;
    }

    // `action` with its steps read (step_sides), made with index_args.
    std::vector<StepSides> step_sides_;
    size_t step_sides_of = 0;     // action.size() when they were made
    size_t step_sides_args_ = 0;  // args.size() then
    // The sides of step `i`, or nullptr when they were not made (then the
    // envelope reads the step's texts).
    const StepSides* step_sides(size_t i) const {
        return step_sides_of == action.size() && step_sides_args_ == args.size() && i < step_sides_.size()
                   ? &step_sides_[i]
                   : nullptr;
    }
    // The arguments the action sequence reads (each term of a step's `target`
    // and `by`, each argument its conditions name), each once, made with
    // index_args; empty and not `action_args_read_` when a step's expression
    // is not in the syntax or a name is not exactly an argument's name or
    // alias (the steps then read more than the arguments listed).
    std::vector<uint16_t> action_args_;
    bool action_args_read_ = false;
    // Those arguments' indices in `args`, or nullptr when not made or not read.
    const std::vector<uint16_t>* action_args() const {
        return action_args_read_ && step_sides_of == action.size() && step_sides_args_ == args.size() ? &action_args_
                                                                                                     : nullptr;
    }

    // Whether the action sequence reads the argument the address `axis`
    // (X, Y or Z) stands for (arg_for_address) or the positioning argument of
    // that axis in plane `plane` (17, 18, 19; position_arg); true when the
    // steps read more than action_args lists. Kept for each plane and axis
    // by index_action_args: the walk asks on every repeated call.
    bool action_reads_axis(int plane, char axis) const;
    bool reads_axis_now(int plane, char axis) const;  // worked out, not kept
    std::array<bool, 9> action_reads_axis_{};  // by plane and axis, as position_args_
    bool action_reads_axis_made_ = false;

    // The positioning-plane argument (ArgRole::Position) of axis `axis` in
    // plane `plane` (17, 18, 19), the last one listed when several are;
    // nullptr when none is. Looked up in position_args_, made with
    // index_args; for another number of arguments, among the arguments.
    const ArgSpec* position_arg(int plane, char axis) const;
    std::array<int16_t, 9> position_args_{};  // by plane and axis X/Y/Z: 1 + the index, 0: none
    size_t position_args_of = 0;              // 1 + args.size() when they were made (0: not made)

    // By name or alias, case-insensitive.
    const ArgSpec* arg(std::string_view name) const;
    // In the G-code macro form: the argument an address stands for (through
    // `gcode_form->address_map`, else by name).
    const ArgSpec* arg_for_address(std::string_view address) const;
    bool has_form(MacroForm form) const;
    bool has(Hazard h) const { return hazards[static_cast<std::size_t>(h)]; }
    const Reading* reading(std::string_view id) const;
};
using CycleSpec = MacroSpec;

// A plane-designation table as printed in a manual, with the reading taken.
struct PlaneTable {
    std::string id;  // the manual's key ("back-counterboring")
    std::string source;
    std::vector<std::string> columns;
    std::array<std::vector<std::string>, 3> rows;  // G17, G18, G19 cells as printed ("" = blank)
    std::string reading;
};

// The common rules of one manual (cautions shared by all its macros).
struct CommonRules {
    std::string id;  // the manual's key ("back-counterboring")
    std::string title;
    std::string source;
    std::vector<CatalogNote> notes;
    std::vector<Reading> readings;
};

class Catalog {
public:
    // The shipped catalog (data/macros.toml, embedded). Throws ConfigError if broken.
    static Catalog builtin();
    // A whole catalog file. Throws ConfigError naming `origin` and the line.
    static Catalog from_toml_text(std::string_view text, std::string origin);

    // Applies a configuration file's `[macro]` table: each `[macro.NAME]` adds
    // a macro, or patches the existing one (`replace = true` redefines it).
    // Throws ConfigError(origin, line, key, message) on a bad entry; on error
    // the catalog is left unchanged.
    void merge(const toml::table& macros_table, const std::string& origin);
    // The same for a `[cycle]` table: each `[cycle.GNN]` adds a fixed cycle,
    // or patches the existing one (`replace = true` redefines it).
    void merge_cycles(const toml::table& cycles_table, const std::string& origin);

    // Registers a G/M-code macro ("G114" -> "OG84L"); an empty macro name
    // removes the registration. Codes are normalised ("g0114" -> "G114");
    // anything but a G or M code throws std::invalid_argument. The macro need
    // not exist yet (find_by_code then returns nullptr).
    void register_code(std::string code, std::string macro);
    // What the control itself does with a G or M code the analysis models
    // ("a motion code" for G0, "ends the program" for M30), or "" when the
    // code is free for a macro. Such a code cannot be registered.
    static std::string_view builtin_meaning(std::string_view code);
    const MacroSpec* find_by_code(std::string_view code) const;
    // The same for the code `letter` `number` ('G', 114) of a block's word:
    // without building the code's text when none such is registered.
    const MacroSpec* find_by_code(char letter, int number) const;
    const std::map<std::string, std::string>& registrations() const { return codes_; }

    // By name as written after CALL/MODIN, case-insensitive ("OZAGR").
    const MacroSpec* find(std::string_view name) const;
    const CycleSpec* find_cycle(int gcode) const;
    const PlaneTable* plane_table(std::string_view id) const;
    const CommonRules* common_rules(std::string_view id) const;

    // In catalog order (the file's order, then macros added by configuration).
    const std::deque<MacroSpec>& macros() const { return macros_; }
    const std::deque<CycleSpec>& cycles() const { return cycles_; }

    // The card shown by `osplint explain NAME` (plain text) and on hover (Markdown).
    std::string render_card(const MacroSpec& spec, bool markdown) const;

private:
    // `macros_` by name, made by merge (the only place macros are added): the
    // same open-addressed table of packed names as MacroSpec::arg_index,
    // holding positions in `macros_`. find() runs for every call of a program.
    // Empty, or made for another number of macros: find() compares the names.
    void index_macros();
    std::vector<std::pair<uint64_t, uint32_t>> macro_index_;
    size_t macro_index_of_ = 0;  // macros_.size() when it was made

    std::deque<MacroSpec> macros_;
    std::deque<CycleSpec> cycles_;
    // The G codes below 1024 that cycles_ holds, as bits: find_cycle, asked
    // of every G code of every block, answers most at once (no cycle).
    std::array<uint64_t, 16> cycle_codes_{};
    std::map<std::string, std::string> codes_;  // "G114" -> "OG84L"
    // codes_'s keys as numbers ('G', 114), made again wherever codes_ changes
    // (register_code, merge).
    void index_codes();
    std::vector<std::pair<char, int>> code_keys_;
    std::vector<PlaneTable> plane_tables_;
    std::vector<CommonRules> common_;
};

// Names as written in the catalog files ("required", "cycle", "MODIN", ...).
std::string_view to_string(ArgOmitted v);
std::string_view to_string(ArgSign v);
std::string_view to_string(ArgRole v);
std::string_view to_string(ArgInFormat v);
std::string_view to_string(MacroForm v);
std::string_view to_string(M52Mode v);
std::string_view to_string(M53Mode v);
std::string_view to_string(RequiredScope v);
std::string_view to_string(MacroUnits v);
std::string_view to_string(G91Mode v);
std::string_view to_string(Hazard v);

// The value constraints of an argument in words ("one of 2, 3; positive"), or "" when there are none.
std::string constraint_text(const ArgSpec& a);
// Whether `left op right` holds for a Relation's operator (> >= < <= == !=).
bool relation_holds(double left, std::string_view op, double right);

// Parses an expression; nullopt when it does not follow the syntax.
std::optional<std::vector<ExprTerm>> parse_catalog_expr(std::string_view text);
// The same, parsed once per thread and kept: the rules and the motion
// evaluator read the catalog's expressions at every call. nullptr when the
// text does not follow the syntax. The pointer stays valid for the thread's
// life; the texts are the catalogs' own, so the store stays small.
const std::vector<ExprTerm>* catalog_expr(std::string_view text);

// The sides of relation `r` of `spec`, read (what MacroSpec::sides holds).
RelationSides relation_sides(const Relation& r, const MacroSpec& spec);
// The sides of action step `step` of `spec`, read (what MacroSpec::step_sides holds).
StepSides step_sides(const ActionStep& step, const MacroSpec& spec);

}  // namespace osplint
