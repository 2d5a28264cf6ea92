// The macro catalog: the shipped data against the manual tables, the schema
// checks, configuration merges and the explain card.
#include <doctest/doctest.h>

#include <cctype>
#include <toml++/toml.h>

#include <fstream>
#include <set>
#include <sstream>
#include <string>

#include "catalog/catalog.h"
#include "support/errors.h"

using namespace osplint;

namespace {

std::string read_file(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    REQUIRE_MESSAGE(in.good(), "cannot open " << path);
    std::ostringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

const std::string& catalog_text() {
    static const std::string text = read_file(std::string(OSPLINT_SOURCE_DIR) + "/data/macros.toml");
    return text;
}

Catalog shipped() { return Catalog::from_toml_text(catalog_text(), "data/macros.toml"); }

toml::table parse_config(std::string_view text) { return toml::parse(text, std::string_view("osplint.toml")); }

// Runs `fn` and returns the ConfigError it throws (fails the test if none).
template <class Fn>
ConfigError expect_config_error(Fn&& fn) {
    try {
        fn();
    } catch (const ConfigError& e) {
        return e;
    }
    FAIL("no ConfigError thrown");
    return ConfigError("", 0, "", "");
}

const ArgSpec& arg_of(const Catalog& cat, std::string_view macro, std::string_view arg) {
    const MacroSpec* m = cat.find(macro);
    REQUIRE_MESSAGE(m != nullptr, "no macro " << macro);
    const ArgSpec* a = m->arg(arg);
    REQUIRE_MESSAGE(a != nullptr, macro << " has no argument " << arg);
    return *a;
}

// The status of each P-name on a printed format line: outside parentheses
// = required, inside = optional.
std::map<std::string, ArgInFormat> scan_format(std::string_view text) {
    std::map<std::string, ArgInFormat> out;
    int depth = 0;
    for (std::size_t i = 0; i < text.size(); ++i) {
        char c = text[i];
        if (c == '(') ++depth;
        else if (c == ')') --depth;
        else if (c == 'P' && (i == 0 || text[i - 1] == ' ' || text[i - 1] == '(')) {
            std::size_t j = i + 1;
            while (j < text.size() && std::isupper(static_cast<unsigned char>(text[j]))) ++j;
            if (j < text.size() && text[j] == '=' && j > i + 1)
                out[std::string(text.substr(i, j - i))] = depth > 0 ? ArgInFormat::Optional : ArgInFormat::Required;
        }
    }
    return out;
}

}  // namespace

TEST_CASE("the shipped catalog parses, and builtin() serves the embedded copy") {
    Catalog cat = shipped();
    CHECK(cat.macros().size() == 16);
    Catalog builtin = Catalog::builtin();
    REQUIRE(builtin.macros().size() == cat.macros().size());
    for (std::size_t i = 0; i < cat.macros().size(); ++i) CHECK(builtin.macros()[i].name == cat.macros()[i].name);
    CHECK(builtin.cycles().size() == cat.cycles().size());
}

TEST_CASE("the action sequence of every shipped macro reads arguments listed in MacroSpec::action_args") {
    // OSP301 remembers a macro's cycle-axis points only when the arguments
    // its steps read are listed (semantics/motion.h, MacroAxisMemo): a step
    // the catalog cannot read, or a name written otherwise than the
    // argument's, would leave the macro out of it without a word.
    const Catalog cat = Catalog::builtin();
    for (const MacroSpec& spec : cat.macros()) {
        CAPTURE(spec.name);
        if (spec.action.empty()) continue;
        const std::vector<uint16_t>* reads = spec.action_args();
        REQUIRE(reads);
        CHECK(!reads->empty());
        // Each step's terms and condition names are among them, each once.
        const std::set<uint16_t> listed(reads->begin(), reads->end());
        CHECK(listed.size() == reads->size());
        for (size_t i = 0; i < spec.action.size(); ++i) {
            const StepSides* sides = spec.step_sides(i);
            REQUIRE(sides);
            for (int k : sides->target_args) CHECK((k >= 0 ? listed.count(static_cast<uint16_t>(k)) == 1 : true));
            for (int k : sides->by_args) CHECK((k >= 0 ? listed.count(static_cast<uint16_t>(k)) == 1 : true));
            for (const ConditionAtom* at : spec.action[i].when.atoms())
                if (!at->arg.empty()) CHECK(listed.count(static_cast<uint16_t>(spec.arg(at->arg) - spec.args.data())) == 1);
        }
    }
    // A step that names no argument of its macro: not listed.
    MacroSpec odd = *cat.find("OZAGR");
    odd.action.push_back(ActionStep{"99", "to nowhere", "", "PZ-QQ", "", {}, false, ""});
    odd.index_args();
    CHECK(odd.action_args() == nullptr);
}

TEST_CASE("every macro of the manuals is present with its call forms, in manual order") {
    Catalog cat = shipped();
    struct Expect {
        const char* name;
        std::vector<MacroForm> forms;
    };
    const std::vector<Expect> expected = {
        {"OG87C", {MacroForm::Modin}},
        {"OG87N", {MacroForm::Modin}},
        {"OG87K", {MacroForm::Modin}},
        {"OG87M", {MacroForm::Modin}},
        {"OZAGR", {MacroForm::Call}},
        {"OM100", {MacroForm::Call}},
        {"OLPEX", {MacroForm::Call}},
        {"OLPEY", {MacroForm::Call}},
        {"OLAPX", {MacroForm::Call, MacroForm::GCode}},
        {"OLAPY", {MacroForm::Call, MacroForm::GCode}},
        {"OKYOX", {MacroForm::Call, MacroForm::Modin, MacroForm::GCode}},
        {"OKYOY", {MacroForm::Call, MacroForm::Modin, MacroForm::GCode}},
        {"OKYLX", {MacroForm::Call}},
        {"OKYLY", {MacroForm::Call}},
        {"OG84L", {MacroForm::GCode}},
        {"OC84L", {MacroForm::MCode}},
    };
    REQUIRE(cat.macros().size() == expected.size());
    for (std::size_t i = 0; i < expected.size(); ++i) {
        CAPTURE(expected[i].name);
        const MacroSpec* m = cat.find(expected[i].name);
        REQUIRE(m != nullptr);
        CHECK(m->forms == expected[i].forms);
        CHECK(cat.macros()[i].name == expected[i].name);  // stable, manual order
        CHECK(!m->title.empty());
        CHECK(!m->family.empty());
        CHECK(!m->manual.empty());
        CHECK(!m->source.empty());
    }
    CHECK(cat.find("ozagr") == cat.find("OZAGR"));  // case-insensitive
    CHECK(cat.find("OXXXX") == nullptr);
}

TEST_CASE("OG87C against its manual table (000:L138-188)") {
    Catalog cat = shipped();
    const MacroSpec& m = *cat.find("OG87C");
    for (const char* a : {"PR", "PZ", "PC", "PD"}) {
        CAPTURE(a);
        CHECK(arg_of(cat, "OG87C", a).required());
    }
    CHECK_FALSE(arg_of(cat, "OG87C", "PI").required());  // reading og87c-pi-required: default 0, at-least-one rule
    CHECK(arg_of(cat, "OG87C", "PI").default_value == 0.0);
    CHECK(arg_of(cat, "OG87C", "PI").format_status(MacroForm::Modin) == ArgInFormat::Required);
    CHECK(arg_of(cat, "OG87C", "PG").allowed == std::vector<double>{2, 3});
    CHECK(arg_of(cat, "OG87C", "PG").default_value == 3.0);
    CHECK(arg_of(cat, "OG87C", "PM").allowed == std::vector<double>{52});
    CHECK(m.m52 == M52Mode::IgnoredUsePM52);
    CHECK(m.m53 == M53Mode::ReturnToPT);
    CHECK(m.has(Hazard::G60NcylCollision));
    CHECK(m.has(Hazard::OverwritesVc120To128));
    CHECK(m.has(Hazard::RepeatCountAbnormal));
    CHECK(m.units == MacroUnits::MmOnly);
    CHECK(m.g91 == G91Mode::CycleAxisAbsolute);
    // Note 2 and its plane-table inference for G18/G19.
    REQUIRE(m.at_least_one.size() == 3);
    CHECK(m.at_least_one[0].plane == 17);
    CHECK(m.at_least_one[0].args == std::vector<std::string>{"PI", "PJ"});
    CHECK_FALSE(m.at_least_one[0].inferred);
    CHECK(m.at_least_one[1].plane == 18);
    CHECK(m.at_least_one[1].args == std::vector<std::string>{"PI", "PK"});
    CHECK(m.at_least_one[1].inferred);
    CHECK(m.at_least_one[2].args == std::vector<std::string>{"PJ", "PK"});
    // Plane table: PK has no axis in G17, PI none in G19.
    CHECK_FALSE(arg_of(cat, "OG87C", "PK").axis(17).has_value());
    CHECK(arg_of(cat, "OG87C", "PK").axis(18) == 'Z');
    CHECK_FALSE(arg_of(cat, "OG87C", "PI").axis(19).has_value());
    CHECK(m.reading("og87c-pi-required") != nullptr);
    CHECK(m.reading("og87c-pi-required")->open);
}

TEST_CASE("back-counterbore macros: strokes, undocumented PP/PD, defaults") {
    Catalog cat = shipped();
    for (const char* m : {"OG87N", "OG87K", "OG87M"}) {
        CAPTURE(m);
        const ArgSpec& pp = arg_of(cat, m, "PP");
        CHECK(pp.undocumented);
        CHECK(pp.omitted == ArgOmitted::Unknown);
        CHECK(arg_of(cat, m, "PL").required());
        CHECK(arg_of(cat, m, "PL").role == ArgRole::Stroke);
    }
    CHECK(arg_of(cat, "OG87N", "PI").required());
    CHECK(arg_of(cat, "OG87N", "PJ").required());
    CHECK(cat.find("OG87K")->arg("PI") == nullptr);  // reading og87k-figure-pi: figure label only
    CHECK(arg_of(cat, "OG87K", "PFB").format_status(MacroForm::Modin) == ArgInFormat::Absent);  // reading og87k-pfb

    const ArgSpec& pd = arg_of(cat, "OZAGR", "PD");
    CHECK(pd.undocumented);
    CHECK(arg_of(cat, "OZAGR", "PL").default_value == 5.0);
    CHECK(arg_of(cat, "OZAGR", "PL").omitted == ArgOmitted::Default);
    CHECK(arg_of(cat, "OM100", "PL").default_value == 5.0);
    CHECK(arg_of(cat, "OM100", "PFA").default_value == 1000.0);
    CHECK(arg_of(cat, "OM100", "PFA").default_text == "1000");
    CHECK(arg_of(cat, "OZAGR", "PFA").default_text == "PF*4");
    CHECK_FALSE(arg_of(cat, "OZAGR", "PFA").default_value.has_value());
    // reading pt-error-when-omitted: PT is not required by itself; M53 without PT is the alarm.
    CHECK(arg_of(cat, "OZAGR", "PT").omitted == ArgOmitted::None);
    CHECK(arg_of(cat, "OM100", "PT").omitted == ArgOmitted::None);
    CHECK(cat.find("OZAGR")->m53 == M53Mode::ReturnToPT);
    CHECK(cat.find("OZAGR")->reading("pt-error-when-omitted")->open);
    for (const char* a : {"PR", "PZ", "PI"}) {
        CHECK(arg_of(cat, "OZAGR", a).required());
        CHECK(arg_of(cat, "OM100", a).required());
    }
}

TEST_CASE("wall finishing: OLPEX table wins, predecessors keep PQ required") {
    Catalog cat = shipped();
    const ArgSpec& pk = arg_of(cat, "OLPEX", "PK");
    CHECK(pk.required());  // reading olpex-pk-required
    CHECK(pk.format_status(MacroForm::Call) == ArgInFormat::Optional);
    CHECK(pk.sign == ArgSign::NonNegative);
    CHECK(arg_of(cat, "OLPEX", "PA").sign == ArgSign::NonNegative);
    CHECK_FALSE(arg_of(cat, "OLPEX", "PA").required());
    CHECK(arg_of(cat, "OLPEX", "PI").negative_allowed);
    CHECK(cat.find("OLPEX")->arg("PT") == nullptr);  // reading olpex-no-pt
    CHECK(cat.find("OLPEX")->m53 == M53Mode::Undocumented);
    // Travel axis and end-point vectors per macro (001:L61-87, L267-270).
    CHECK(arg_of(cat, "OLPEX", "PI").axis(18) == 'Z');
    CHECK(arg_of(cat, "OLPEY", "PI").axis(18) == 'X');
    CHECK(arg_of(cat, "OLPEX", "PJ").axis(17) == 'Y');
    CHECK(arg_of(cat, "OLPEY", "PJ").axis(17) == 'X');
    CHECK(arg_of(cat, "OLPEX", "PB").axis(19) == 'Y');
    CHECK(arg_of(cat, "OLPEY", "PB").axis(19) == 'Z');

    // The manual's example OEX01 (001:L313-343) gives no PQ: it must be reported.
    for (const char* name : {"OLAPX", "OLAPY"}) {
        CAPTURE(name);
        const MacroSpec& m = *cat.find(name);
        std::set<std::string> given = {"PX", "PY", "PR", "PZ", "PI", "PK", "PP", "PF"};
        std::vector<std::string> missing;
        for (const auto& a : m.args)
            if (a.required() && !given.count(a.name)) missing.push_back(a.name);
        CHECK(missing == std::vector<std::string>{"PQ"});
        REQUIRE(m.gcode_form.has_value());
        const ArgSpec* q = m.arg_for_address("Q");
        REQUIRE(q != nullptr);
        CHECK(q->name == "PQ");  // in the G-code form Q is the pitch (reading gcode-q-is-pq)
        CHECK(q->role == ArgRole::Pitch);
        CHECK(m.arg_for_address("FA")->name == "PFA");
        CHECK(m.has(Hazard::RepeatCountAbnormal));
    }
}

TEST_CASE("keyways: OKYLX follows its table, not the copied format line (reading okylx-format-line)") {
    Catalog cat = shipped();
    for (const char* name : {"OKYLX", "OKYLY"}) {
        CAPTURE(name);
        const MacroSpec& m = *cat.find(name);
        CHECK(m.arg("PD") != nullptr);
        CHECK(m.arg("PD")->required());
        CHECK(m.arg("PQ") == nullptr);
        CHECK(m.arg("PK") == nullptr);
        CHECK(m.arg("PP") == nullptr);
        CHECK(m.g91 == G91Mode::Unsupported);
        CHECK(m.forms == std::vector<MacroForm>{MacroForm::Call});
        CHECK(m.reading("okylx-format-line") != nullptr);
    }
    // OKYOX: PX/PY required by the CALL format only; the table says none (reading px-py-optional).
    const ArgSpec& px = arg_of(cat, "OKYOX", "PX");
    CHECK(px.omitted == ArgOmitted::None);
    CHECK(px.format_status(MacroForm::Call) == ArgInFormat::Required);
    CHECK(px.format_status(MacroForm::Modin) == ArgInFormat::Absent);
    for (const char* a : {"PR", "PZ", "PI", "PJ", "PD"}) CHECK(arg_of(cat, "OKYOX", a).required());
    CHECK(arg_of(cat, "OKYOX", "PJ").negative_allowed);
    CHECK(cat.find("OKYOX")->has(Hazard::G60NcylCollision));
    CHECK(cat.find("OKYOX")->arg_for_address("T")->name == "PT");
}

TEST_CASE("OG84L is a G-code macro on G114, cancelled by OC84L on M204") {
    Catalog cat = shipped();
    const MacroSpec* g114 = cat.find_by_code("G114");
    REQUIRE(g114 != nullptr);
    CHECK(g114->name == "OG84L");
    CHECK(cat.find_by_code("g0114") == g114);
    CHECK(g114->arg("Z")->required());
    CHECK(g114->arg("R")->required());
    CHECK(g114->arg("PZ") == g114->arg("Z"));  // reading og84l-address-names alias
    CHECK(g114->arg("FA")->omitted == ArgOmitted::Default);
    CHECK(g114->arg("FA")->default_text == "PF (= F)");
    CHECK(g114->arg("S")->format_status(MacroForm::GCode) == ArgInFormat::Absent);  // reading og84l-s
    CHECK(g114->g91 == G91Mode::FollowsG91);
    CHECK(g114->m52 == M52Mode::FixedCycle);
    CHECK(g114->m53 == M53Mode::FixedCycle);
    CHECK_FALSE(g114->has(Hazard::G60NcylCollision));
    CHECK(g114->tapping);
    CHECK(g114->required_scope == RequiredScope::CycleStart);
    CHECK(g114->cancel == "OC84L");

    const MacroSpec* m204 = cat.find_by_code("M204");
    REQUIRE(m204 != nullptr);
    CHECK(m204->name == "OC84L");
    CHECK(m204->args.empty());
    CHECK(m204->cancels == "OG84L");
    CHECK(cat.find_by_code("G115") == nullptr);
}

TEST_CASE("plane mapping: cycle-axis arguments follow the plane's cycle axis") {
    Catalog cat = shipped();
    CHECK(arg_of(cat, "OZAGR", "PR").axis(17) == 'Z');
    CHECK(arg_of(cat, "OZAGR", "PR").axis(18) == 'Y');
    CHECK(arg_of(cat, "OZAGR", "PR").axis(19) == 'X');
    CHECK(arg_of(cat, "OG87C", "PZ").axis(18) == 'Y');
    CHECK(arg_of(cat, "OG87C", "PX").axis(18) == 'Z');
    CHECK(arg_of(cat, "OG87C", "PY").axis(19) == 'Z');
    CHECK_FALSE(arg_of(cat, "OG87C", "PR").axis(16).has_value());

    // Every argument named in a printed plane table maps as the table says:
    // bare letters literally, "L(n)" cells by axis number.
    for (const auto& m : cat.macros()) {
        const PlaneTable* pt = cat.plane_table(m.plane_table);
        if (!pt) continue;
        for (std::size_t c = 0; c < pt->columns.size(); ++c) {
            std::string col = pt->columns[c];
            std::string argname = col.substr(0, col.find(' '));
            if (col.find(' ') != std::string::npos && col.substr(col.find(' ') + 1) != m.name) continue;
            if (m.plane_table == "back-counterboring" && (argname == "PI" || argname == "PJ" || argname == "PK") &&
                m.name != "OG87C")
                continue;  // note 2 of the table: its PI/PJ/PK apply to OG87C only
            const ArgSpec* a = m.arg(argname);
            if (!a) continue;
            for (int row = 0; row < 3; ++row) {
                CAPTURE(m.name);
                CAPTURE(argname);
                CAPTURE(row);
                std::string cell = pt->rows[row][c];
                char want = 0;
                if (cell.size() == 4) {  // "X(2)": the axis numbered like this column's G17 cell
                    char number = pt->rows[0][c][2];
                    for (std::size_t k = 0; k < 3; ++k)
                        if (pt->rows[row][k][2] == number) want = pt->rows[row][k][0];
                } else if (!cell.empty()) {
                    want = cell[0];
                }
                CHECK(a->axes[row] == want);
            }
        }
    }
}

TEST_CASE("format lines agree with the per-argument format column") {
    Catalog cat = shipped();
    for (const auto& m : cat.macros()) {
        for (const auto& f : m.formats) {
            CAPTURE(m.name);
            CAPTURE(f.text);
            if (f.form == MacroForm::Call) CHECK(f.text.rfind("CALL " + m.name + " ", 0) == 0);
            if (f.form == MacroForm::Modin) CHECK(f.text.rfind("MODIN " + m.name + " ", 0) == 0);
            auto printed = scan_format(f.text);
            for (const auto& entry : printed) {
                const std::string& name = entry.first;
                CAPTURE(name);
                const ArgSpec* a = m.arg(name);
                if (!a) {
                    CHECK(m.reading("okylx-format-line") != nullptr);  // only OKYLX/OKYLY print foreign names
                    continue;
                }
                CHECK(a->format_status(f.form) == entry.second);
            }
            for (const auto& a : m.args)
                if (!printed.count(a.name) && f.form != MacroForm::GCode)
                    CHECK_MESSAGE(a.format_status(f.form) == ArgInFormat::Absent, a.name);
        }
    }
}

TEST_CASE("fixed cycles of the fixed cycles manual") {
    Catalog cat = shipped();
    for (int g : {77, 78, 79, 81, 82, 83, 84, 85, 86, 87, 88, 89, 186, 73, 74, 76}) {
        CAPTURE(g);
        const CycleSpec* c = cat.find_cycle(g);
        REQUIRE(c != nullptr);
        CHECK(c->kind == SpecKind::FixedCycle);
        CHECK(c->required_scope == RequiredScope::CycleStart);
    }
    CHECK(cat.find_cycle(80) == nullptr);
    for (int g : {73, 74, 76, 79, 89, 186}) CHECK_FALSE(cat.find_cycle(g)->args_documented);

    const CycleSpec& g78 = *cat.find_cycle(78);
    CHECK(g78.arg("Q")->required());
    CHECK(g78.arg("K")->required());
    CHECK(g78.arg("Q")->sign == ArgSign::Positive);
    CHECK(g78.arg("K")->sign == ArgSign::Positive);
    CHECK(g78.arg("Q")->always_incremental);
    CHECK(g78.arg("K")->always_incremental);
    REQUIRE(g78.relations.size() == 1);
    CHECK(g78.relations[0].left == "Q");
    CHECK(g78.relations[0].op == ">");
    CHECK(g78.relations[0].right == "K");
    CHECK(g78.relations[0].source == "004:L80");

    for (int g : {81, 82, 84, 85, 86})
        for (const char* a : {"Z", "R", "F"}) {
            CAPTURE(g);
            CAPTURE(a);
            CHECK(cat.find_cycle(g)->arg(a)->required());
        }
    CHECK(cat.find_cycle(83)->arg("Q")->required());
    CHECK(cat.find_cycle(87)->arg("Q")->required());
    CHECK(cat.find_cycle(83)->arg("J")->always_incremental);
    CHECK_FALSE(cat.find_cycle(81)->arg("X")->required());
    CHECK(cat.find_cycle(81)->arg("L")->g91_only);
    CHECK(cat.find_cycle(84)->tapping);
    CHECK_FALSE(cat.find_cycle(81)->tapping);
    CHECK(cat.find_cycle(84)->formats.size() == 2);
    // G88: both Q and K accepted as the Z shift (reading g88-q-or-k), neither required.
    CHECK(cat.find_cycle(88)->arg("Q") != nullptr);
    CHECK(cat.find_cycle(88)->arg("K") != nullptr);
    CHECK_FALSE(cat.find_cycle(88)->arg("K")->required());
    CHECK(cat.find_cycle(88)->arg("I")->omitted == ArgOmitted::Default);
}

TEST_CASE("action sequences carry evaluable cycle-axis targets") {
    Catalog cat = shipped();
    auto targets = [&](std::string_view name) {
        std::vector<std::string> out;
        for (const auto& st : cat.find(name)->action)
            if (!st.target.empty()) out.push_back(st.step + ":" + st.target);
        return out;
    };
    CHECK(targets("OZAGR") == std::vector<std::string>{"2:PR", "3a:PR-PJ", "3b:PR-PJ-PD", "3c:PZ-PI-PL", "5:PZ",
                                                       "7:PZ-1", "9:PZ+2", "10:PR", "11:PT"});
    CHECK(targets("OM100") ==
          std::vector<std::string>{"2:PR", "3a:PZ+PK+PL", "3b:PZ+PK", "4:PZ-PL", "6:PZ", "9:PR", "10:PT"});
    CHECK(targets("OG87C") == std::vector<std::string>{"2:PA", "4:PR", "8:PZ", "11:PR", "14:PA", "16:PT"});
    CHECK(targets("OG84L") == std::vector<std::string>{"2:R", "3:Z+L", "5:R"});
    // The T-point return happens only in M53 mode.
    CHECK(cat.find("OG87C")->action.at(15).when.text() == "M53");
    // Every expression in the catalog parses and names arguments of its macro.
    for (const auto* list : {&cat.macros(), &cat.cycles()})
        for (const auto& m : *list) {
            for (const auto& st : m.action)
                for (const std::string* e : {&st.target, &st.by}) {
                    if (e->empty()) continue;
                    auto terms = parse_catalog_expr(*e);
                    REQUIRE_MESSAGE(terms.has_value(), m.name << " " << *e);
                    for (const auto& t : *terms)
                        if (!t.name.empty()) CHECK_MESSAGE(m.arg(t.name) != nullptr, m.name << " " << t.name);
                }
        }
}

TEST_CASE("an argument found through the index is the one the names give") {
    const Catalog& cat = Catalog::builtin();
    size_t specs = 0, lookups = 0;
    auto check_spec = [&](const MacroSpec& spec) {
        ++specs;
        CHECK_MESSAGE((spec.args.empty() || !spec.arg_index.empty()), spec.name);
        MacroSpec plain = spec;  // without the index: arg() compares the names
        plain.arg_index.clear();
        std::vector<std::string> names = {"", "P", "PXX", "NOSUCHNAME", "ABCDEFGHI"};
        for (const auto& a : spec.args) {
            names.push_back(a.name);
            for (const auto& al : a.aliases) names.push_back(al);
        }
        for (size_t k = 0, n = names.size(); k < n; ++k) {
            std::string lower = names[k];
            for (char& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
            names.push_back(lower);
        }
        for (const auto& name : names) {
            ++lookups;
            const ArgSpec* a = spec.arg(name);
            const ArgSpec* b = plain.arg(name);
            CHECK_MESSAGE((a ? a - spec.args.data() : -1) == (b ? b - plain.args.data() : -1),
                          spec.name << " " << name);
        }
    };
    for (const auto& m : cat.macros()) check_spec(m);
    for (const auto& c : cat.cycles()) check_spec(c);
    CHECK(specs > 10);
    MESSAGE(specs << " macros, " << lookups << " names");
}

TEST_CASE("a positioning argument found through the index is the one the roles and axes give") {
    // MacroSpec::position_arg, made with index_args, against the search
    // among the arguments it falls back to (a spec whose arguments changed
    // since): for every macro and cycle, plane and axis.
    const Catalog& cat = Catalog::builtin();
    size_t found = 0;
    auto check_spec = [&](const MacroSpec& spec) {
        CHECK_MESSAGE(spec.position_args_of == spec.args.size() + 1, spec.name);
        MacroSpec plain = spec;
        plain.position_args_of = 0;  // not made: the arguments are searched
        for (int plane : {17, 18, 19, 20})
            for (char axis : {'X', 'Y', 'Z', 'A', 'x'}) {
                const ArgSpec* a = spec.position_arg(plane, axis);
                const ArgSpec* b = plain.position_arg(plane, axis);
                CHECK_MESSAGE((a ? a - spec.args.data() : -1) == (b ? b - plain.args.data() : -1),
                              spec.name << " G" << plane << " " << axis);
                if (a) {
                    ++found;
                    CHECK(a->role == ArgRole::Position);
                    CHECK(a->axis(plane) == axis);
                }
            }
    };
    for (const auto& m : cat.macros()) check_spec(m);
    for (const auto& c : cat.cycles()) check_spec(c);
    CHECK(found > 20);
    // An argument added since the index was made: the search finds it.
    MacroSpec grown = *cat.find("OZAGR");
    const ArgSpec* px = grown.position_arg(17, 'X');
    REQUIRE(px);
    ArgSpec extra = *px;
    extra.name = "PXX";
    grown.args.push_back(extra);
    const ArgSpec* last = grown.position_arg(17, 'X');
    REQUIRE(last);
    CHECK(last->name == "PXX");
}

TEST_CASE("catalog expressions") {
    auto t = parse_catalog_expr("PZ-PI-PL");
    REQUIRE(t.has_value());
    REQUIRE(t->size() == 3);
    CHECK((*t)[0].name == "PZ");
    CHECK((*t)[0].sign == 1);
    CHECK((*t)[1].sign == -1);
    CHECK((*t)[2].name == "PL");
    auto n = parse_catalog_expr("PZ + 1.5");
    REQUIRE(n.has_value());
    CHECK((*n)[1].name.empty());
    CHECK((*n)[1].number == 1.5);
    CHECK(parse_catalog_expr("-PA")->at(0).sign == -1);
    CHECK_FALSE(parse_catalog_expr("PZ*2").has_value());
    CHECK_FALSE(parse_catalog_expr("PZ+").has_value());
    CHECK_FALSE(parse_catalog_expr("").has_value());
    // Parsed once, then the same terms every time.
    const auto* once = catalog_expr("PZ - PI - PL");
    REQUIRE(once);
    CHECK(once->size() == 3);
    CHECK((*once)[2].name == "PL");
    CHECK(catalog_expr("PZ - PI - PL") == once);
    CHECK(catalog_expr("PZ*2") == nullptr);
    CHECK(catalog_expr("PZ*2") == nullptr);
}

TEST_CASE("the shipped catalog is ASCII") {
    for (unsigned char c : catalog_text()) {
        if (c >= 0x80) {
            FAIL("non-ASCII byte in data/macros.toml");
            break;
        }
    }
    CHECK(catalog_text().size() > 1000);
}

TEST_CASE("merge: a shop macro, a patched reading and a moved registration") {
    Catalog cat = shipped();
    const MacroSpec* ozagr_before = cat.find("OZAGR");
    cat.merge(parse_config(R"(
[OFACE]
family = "face-milling"
title = "Shop face milling"
forms = ["CALL"]
codes = ["G115"]
[OFACE.arg]
PZ = { meaning = "Z of the face", omitted = "required", role = "cycle", axis = "cycle", in_format = "required" }
PF = { meaning = "feed", omitted = "default", default = 800, role = "feed" }

[OZAGR.arg.PT]
omitted = "required"

[OG84L]
codes = ["G113"]
)"),
              "osplint.toml");
    const MacroSpec* face = cat.find("OFACE");
    REQUIRE(face != nullptr);
    CHECK(face->origin == "osplint.toml");
    CHECK(face->arg("PZ")->required());
    CHECK(face->arg("PZ")->axis(19) == 'X');
    CHECK(face->arg("PF")->default_value == 800.0);
    CHECK(cat.find_by_code("G115") == face);
    CHECK(cat.macros().back().name == "OFACE");
    // The patch changed only PT's reading; the rest of OZAGR is intact and in place.
    CHECK(cat.find("OZAGR") == ozagr_before);
    CHECK(arg_of(cat, "OZAGR", "PT").required());
    CHECK(arg_of(cat, "OZAGR", "PT").meaning == "return position for M53");
    CHECK(arg_of(cat, "OZAGR", "PR").required());
    CHECK(cat.find("OZAGR")->args.size() == 15);
    // OG84L moved from G114 to G113.
    CHECK(cat.find_by_code("G113")->name == "OG84L");
    CHECK(cat.find_by_code("G114") == nullptr);
    CHECK(cat.find_by_code("M204")->name == "OC84L");
    // A block's word finds the same by its letter and number.
    CHECK(cat.find_by_code('G', 113) == cat.find_by_code("G113"));
    CHECK(cat.find_by_code('g', 115) == face);
    CHECK(cat.find_by_code('G', 114) == nullptr);
    CHECK(cat.find_by_code('M', 204)->name == "OC84L");
    CHECK(cat.find_by_code('M', 113) == nullptr);
}

TEST_CASE("merge: replace = true redefines a macro; register_code overrides") {
    Catalog cat = shipped();
    cat.merge(parse_config(R"(
[OG87K]
replace = true
title = "Shop version"
forms = ["CALL"]
[OG87K.arg.PQ]
omitted = "required"
role = "pitch"
)"),
              "shop.toml");
    const MacroSpec* k = cat.find("OG87K");
    REQUIRE(k != nullptr);
    CHECK(k->title == "Shop version");
    CHECK(k->args.size() == 1);
    CHECK(k->arg("PL") == nullptr);
    CHECK(k->forms == std::vector<MacroForm>{MacroForm::Call});

    // A replacement keeps the registrations unless it names its own codes.
    cat.merge(parse_config("[OG84L]\nreplace = true\nforms = [\"GCODE\"]\n"), "shop.toml");
    CHECK(cat.find_by_code("G114") == cat.find("OG84L"));
    CHECK(cat.find("OG84L")->args.empty());

    cat.register_code("G114", "OLAPX");
    CHECK(cat.find_by_code("G114")->name == "OLAPX");
    CHECK(cat.find_by_code('G', 114)->name == "OLAPX");
    cat.register_code("g0115", "OLAPY");
    CHECK(cat.find_by_code('G', 115)->name == "OLAPY");
    cat.register_code("g114", "");
    CHECK(cat.find_by_code("G114") == nullptr);
    CHECK(cat.find_by_code('G', 114) == nullptr);
    CHECK(cat.find_by_code('G', 115)->name == "OLAPY");
    CHECK_THROWS_AS(cat.register_code("X10", "OZAGR"), std::invalid_argument);
}

TEST_CASE("bad configuration entries name the file, line and key") {
    Catalog cat = shipped();
    SUBCASE("unknown key") {
        auto e = expect_config_error([&] {
            cat.merge(parse_config("[OZAGR]\ntitle = \"x\"\n\n[OZAGR.arg.PT]\nomited = \"required\"\n"), "osplint.toml");
        });
        CHECK(e.file() == "osplint.toml");
        CHECK(e.line() == 5);
        CHECK(e.key() == "macro.OZAGR.arg.PT.omited");
        CHECK(std::string(e.what()).find("unknown key") != std::string::npos);
    }
    SUBCASE("wrong type") {
        auto e = expect_config_error([&] {
            cat.merge(parse_config("[OZAGR]\n\ntapping = \"yes\"\n"), "osplint.toml");
        });
        CHECK(e.line() == 3);
        CHECK(e.key() == "macro.OZAGR.tapping");
        CHECK(std::string(e.what()).find("expected true or false") != std::string::npos);
    }
    SUBCASE("a key of catalog schema 1 names what to write instead") {
        const std::pair<const char*, const char*> cases[] = {
            {"mm_only = true", "units = \"mm\""},
            {"cycle_args_absolute_g91 = true", "g91 = \"cycle-axis-absolute\""},
            {"g91_forbidden = true", "g91 = \"unsupported\""},
            {"g60_ncyl_forbidden = false", "\"g60-ncyl-collision\" in hazards"},
            {"vc120_128_clobbered = true", "\"overwrites-vc120-vc128\" in hazards"},
            {"q_repeat_unsafe = true", "\"repeat-count-abnormal\" in hazards"},
        };
        for (const auto& c : cases) {
            const char* line = c.first;
            const char* now = c.second;
            CAPTURE(line);
            auto e = expect_config_error([&] {
                cat.merge(parse_config(std::string("[OZAGR]\ntitle = \"t\"\n") + line + "\n"), "osplint.toml");
            });
            CHECK(e.line() == 3);
            CHECK(std::string(e.what()).find(now) != std::string::npos);
        }
        CHECK(cat.find("OZAGR")->has(Hazard::G60NcylCollision));
    }
    SUBCASE("hazards: known names, each once") {
        auto e = expect_config_error([&] {
            cat.merge(parse_config("[OZAGR]\nhazards = [\"g60-ncyl\"]\n"), "osplint.toml");
        });
        CHECK(e.key() == "macro.OZAGR.hazards");
        CHECK(std::string(e.what()).find("\"g60-ncyl-collision\"") != std::string::npos);
        auto e2 = expect_config_error([&] {
            cat.merge(parse_config("[OZAGR]\nhazards = [\"g60-ncyl-collision\", \"g60-ncyl-collision\"]\n"),
                      "osplint.toml");
        });
        CHECK(e2.key() == "macro.OZAGR.hazards");
        CHECK(std::string(e2.what()).find("twice") != std::string::npos);
        // A shop takes a hazard off a shipped macro by writing the list without it.
        cat.merge(parse_config("[OZAGR]\nhazards = [\"overwrites-vc120-vc128\"]\n"), "osplint.toml");
        CHECK_FALSE(cat.find("OZAGR")->has(Hazard::G60NcylCollision));
        CHECK(cat.find("OZAGR")->has(Hazard::OverwritesVc120To128));
        CHECK_FALSE(cat.find("OZAGR")->has(Hazard::RepeatCountAbnormal));
    }
    SUBCASE("a condition is parsed when the catalog loads") {
        struct Bad {
            const char* when;
            const char* says;
        };
        const Bad cases[] = {
            {"G16", "unknown condition \"G16\""},
            {"(M53 or G90", "')' is missing"},
            {"M53 or", "missing"},
            {"and M53", "needs a condition before it"},
            {"M53 G90", "unexpected \"G90\""},
            {"PM=fifty", "unknown condition"},
            {"given:PW", "\"PW\" is not an argument of OZAGR"},
            {"PW=52", "\"PW\" is not an argument of OZAGR"},
        };
        for (const auto& c : cases) {
            CAPTURE(c.when);
            auto e = expect_config_error([&] {
                cat.merge(parse_config(std::string("[OZAGR]\ntitle = \"t\"\naction = [\n  { step = \"1\", when = \"") +
                                       c.when + "\" } ]\n"),
                          "osplint.toml");
            });
            CHECK(e.key() == "macro.OZAGR.action[0].when");
            CHECK(std::string(e.what()).find(c.says) != std::string::npos);
        }
        auto e = expect_config_error([&] {
            cat.merge(parse_config("[OZAGR]\nrelations = [ { left = \"PR\", op = \">\", right = \"PZ\", when = 52 } ]\n"),
                      "osplint.toml");
        });
        CHECK(e.key() == "macro.OZAGR.relations[0].when");
    }
    SUBCASE("a caution needs an id, a condition and a text; its severity is warning or info") {
        struct Bad {
            const char* entry;
            const char* key;
            const char* says;
        };
        const Bad cases[] = {
            {"{ when = \"M4\", text = \"t\" }", "macro.OZAGR.cautions[0].id", "needs 'id'"},
            {"{ id = \"x\", text = \"t\" }", "macro.OZAGR.cautions[0].when", "needs 'when'"},
            {"{ id = \"x\", when = \"M4\" }", "macro.OZAGR.cautions[0].text", "needs 'text'"},
            {"{ id = \"x\", when = \"M6\", text = \"t\" }", "macro.OZAGR.cautions[0].when", "unknown condition"},
            {"{ id = \"x\", when = \"not given:PW\", text = \"t\" }", "macro.OZAGR.cautions[0].when",
             "\"PW\" is not an argument of OZAGR"},
            {"{ id = \"x\", when = \"M4\", text = \"t\", severity = \"error\" }",
             "macro.OZAGR.cautions[0].severity", "\"warning\" or \"info\""},
        };
        for (const auto& c : cases) {
            CAPTURE(c.entry);
            auto e = expect_config_error([&] {
                cat.merge(parse_config(std::string("[OZAGR]\ncautions = [ ") + c.entry + " ]\n"), "osplint.toml");
            });
            CHECK(e.key() == c.key);
            CHECK(std::string(e.what()).find(c.says) != std::string::npos);
        }
        // A shop's list replaces the shipped one: an empty list takes every caution off.
        REQUIRE_FALSE(cat.find("OZAGR")->cautions.empty());
        cat.merge(parse_config("[OZAGR]\ncautions = []\n"), "osplint.toml");
        CHECK(cat.find("OZAGR")->cautions.empty());
        cat.merge(parse_config("[OZAGR]\ncautions = [ { id = \"tool\", when = \"G41 or G42\", text = \"t\", "
                               "severity = \"info\" } ]\n"),
                  "osplint.toml");
        REQUIRE(cat.find("OZAGR")->cautions.size() == 1);
        CHECK(cat.find("OZAGR")->cautions[0].info);
        CHECK(cat.find("OZAGR")->cautions[0].when.atoms().size() == 2);
    }
    SUBCASE("bad enum value") {
        auto e = expect_config_error([&] {
            cat.merge(parse_config("[OSHOP]\nforms = [\"CALL\"]\n[OSHOP.arg.PZ]\nrole = \"cycle\"\nomitted = \"maybe\"\n"),
                      "osplint.toml");
        });
        CHECK(e.line() == 5);
        CHECK(e.key() == "macro.OSHOP.arg.PZ.omitted");
        CHECK(std::string(e.what()).find("\"required\"") != std::string::npos);
    }
    SUBCASE("bad call form inside an array") {
        auto e = expect_config_error([&] {
            cat.merge(parse_config("[OSHOP]\ntitle = \"t\"\nforms = [\"CALL\",\n  \"JUMP\"]\n"), "osplint.toml");
        });
        CHECK(e.line() == 4);
        CHECK(e.key() == "macro.OSHOP.forms");
    }
    SUBCASE("a new macro needs forms, a new argument needs omitted and role") {
        auto e = expect_config_error([&] { cat.merge(parse_config("[OSHOP]\ntitle = \"t\"\n"), "osplint.toml"); });
        CHECK(e.key() == "macro.OSHOP.forms");
        auto e2 = expect_config_error([&] {
            cat.merge(parse_config("[OZAGR.arg.PQ]\nmeaning = \"m\"\n"), "osplint.toml");
        });
        CHECK(e2.key() == "macro.OZAGR.arg.PQ.omitted");
        CHECK(e2.line() == 1);
    }
    SUBCASE("an action target must name arguments of the macro") {
        auto e = expect_config_error([&] {
            cat.merge(parse_config("[OZAGR]\naction = [ { step = \"1\", target = \"PZ-PW\" } ]\n"), "osplint.toml");
        });
        CHECK(e.key() == "macro.OZAGR.action[0].target");
    }
    SUBCASE("one merge cannot give a code to two macros") {
        auto e = expect_config_error([&] {
            cat.merge(parse_config("[OSHA]\nforms = [\"GCODE\"]\ncodes = [\"G117\"]\n\n[OSHB]\nforms = [\"GCODE\"]\ncodes = [\"G0117\"]\n"),
                      "osplint.toml");
        });
        CHECK(e.line() == 5);
        CHECK(e.key() == "macro.OSHB.codes");
        CHECK(cat.find_by_code("G117") == nullptr);
    }
    SUBCASE("a failed merge leaves the catalog unchanged") {
        CHECK_THROWS_AS(cat.merge(parse_config("[OFOO]\nforms = [\"CALL\"]\n[OZAGR]\nunits = 1\n"), "osplint.toml"),
                        ConfigError);
        CHECK(cat.find("OFOO") == nullptr);
        CHECK(cat.find("OZAGR")->units == MacroUnits::MmOnly);
    }
    SUBCASE("syntax errors of a catalog file carry the line") {
        auto e = expect_config_error([] { Catalog::from_toml_text("schema = 2\n[macro.OX\n", "cat.toml"); });
        CHECK(e.file() == "cat.toml");
        CHECK(e.line() == 2);
    }
}

TEST_CASE("render_card: terminal text and Markdown") {
    Catalog cat = shipped();
    const MacroSpec& m = *cat.find("OZAGR");
    std::string text = cat.render_card(m, false);
    CHECK(text.rfind("OZAGR - Back counterboring with the BIG back-counterbore bar\n", 0) == 0);
    CHECK(text.find("CALL OZAGR (PX=x PY=y) PR=r PZ=z PI=i") != std::string::npos);
    CHECK(text.find("Arguments (machine axis in G17/G18/G19)") != std::string::npos);
    CHECK(text.find("default 5") != std::string::npos);               // PL
    CHECK(text.find("(undocumented)") != std::string::npos);          // PD
    CHECK(text.find("M53 without PT raises an alarm") != std::string::npos);
    CHECK(text.find("(open, configurable) The table prints PT") != std::string::npos);
    CHECK(text.find("[macro.OZAGR.arg.PT]") != std::string::npos);
    CHECK(text.find("Back counterboring macros manual (OG87EX, 2001-07-30), \"OZAGR (BIG back-counterbore bar)\"") !=
          std::string::npos);
    CHECK(text.find("[\"OZAGR: Action sequence\"]") != std::string::npos);  // a step's source, by its section
    CHECK(text.find("000:L") == std::string::npos);
    CHECK(text.find("**") == std::string::npos);
    std::istringstream lines(text);
    for (std::string l; std::getline(lines, l);) {
        CAPTURE(l);
        CHECK((l.empty() || l.back() != ' '));
    }

    std::string md = cat.render_card(m, true);
    CHECK(md.rfind("### OZAGR: Back counterboring with the BIG back-counterbore bar\n", 0) == 0);
    CHECK(md.find("| Arg | If omitted | Values | G17 | G18 | G19 | Format | Meaning |") != std::string::npos);
    CHECK(md.find("| `PR` | required |") != std::string::npos);
    CHECK(md.find("PF\\*4") != std::string::npos);  // escaped in tables
    CHECK(md.find("```text\nCALL OZAGR") != std::string::npos);

    std::string g114 = cat.render_card(*cat.find("OG84L"), false);
    CHECK(g114.find("Registered to:  G114") != std::string::npos);
    CHECK(g114.find("Cancel:         OC84L (M204)") != std::string::npos);
    std::string g78 = cat.render_card(*cat.find_cycle(78), false);
    CHECK(g78.find("Q > K [\"G78 Variable pick cycle\"]") != std::string::npos);
    CHECK(g78.find("always incremental") != std::string::npos);
}

TEST_CASE("docs/catalog.md: the shop example loads and the error examples are real") {
    std::string doc = read_file(std::string(OSPLINT_SOURCE_DIR) + "/docs/catalog.md");
    std::size_t at = doc.find("# osplint.toml\n");
    REQUIRE(at != std::string::npos);
    std::size_t end = doc.find("```", at);
    REQUIRE(end != std::string::npos);
    toml::table root = parse_config(std::string_view(doc).substr(at, end - at));
    Catalog cat = shipped();
    REQUIRE(root["macro"].as_table() != nullptr);
    cat.merge(*root["macro"].as_table(), "osplint.toml");
    const MacroSpec* face = cat.find("OFACE");
    REQUIRE(face != nullptr);
    CHECK(face->args.size() == 6);
    CHECK(face->arg("PX")->axis(18) == 'Z');
    CHECK(face->action.size() == 2);

    // The three error lines shown in the docs are what the loader prints.
    auto e1 = expect_config_error([&] {
        cat.merge(parse_config("[OZAGR]\ntitle = \"x\"\n\n[OZAGR.arg.PT]\nomited = \"required\"\n"), "osplint.toml");
    });
    CHECK(doc.find(e1.what()) != std::string::npos);
    auto e2 = expect_config_error([&] { cat.merge(parse_config("[OZAGR]\n\nunits = \"millimetres\"\n"), "osplint.toml"); });
    CHECK(doc.find(e2.what()) != std::string::npos);
    auto e3 = expect_config_error([&] {
        cat.merge(parse_config("[OSHOP]\nforms = [\"CALL\"]\n[OSHOP.arg.PZ]\nrole = \"cycle\"\nomitted = \"maybe\"\n"),
                  "osplint.toml");
    });
    CHECK(doc.find(e3.what()) != std::string::npos);
}

TEST_CASE("every override hint of an open reading is a valid patch that changes the macro") {
    Catalog cat = shipped();
    int applied = 0;
    for (const auto& m : cat.macros()) {
        for (const auto& rd : m.readings) {
            if (rd.override_hint.empty()) continue;
            CAPTURE(m.name);
            CAPTURE(rd.override_hint);
            CHECK(rd.open);
            // "[macro.NAME.arg.X] key = value, key = value (comment)"
            std::string hint = rd.override_hint;
            REQUIRE(hint.rfind("[macro." + m.name + ".", 0) == 0);
            std::size_t close = hint.find("] ");
            REQUIRE(close != std::string::npos);
            std::string header = "[" + hint.substr(7, close - 7) + "]";
            std::string body = hint.substr(close + 2);
            if (auto paren = body.find(" ("); paren != std::string::npos) body.resize(paren);
            for (std::size_t p; (p = body.find("\", ")) != std::string::npos;) body.replace(p, 3, "\"\n");
            Catalog patched = cat;
            patched.merge(parse_config(header + "\n" + body + "\n"), "osplint.toml");
            std::string arg = hint.substr(hint.find(".arg.") + 5, close - hint.find(".arg.") - 5);
            const ArgSpec* before = m.arg(arg);
            const ArgSpec* after = patched.find(m.name)->arg(arg);
            REQUIRE(after != nullptr);
            CHECK((before == nullptr || before->omitted != after->omitted));
            ++applied;
        }
    }
    CHECK(applied >= 10);
}

TEST_CASE("every `when` condition of the shipped catalog is typed, on arguments of its macro") {
    Catalog cat = shipped();
    int seen = 0;
    auto check = [&](const MacroSpec& m, const Condition& when) {
        CAPTURE(m.name);
        CAPTURE(when.text());
        REQUIRE_FALSE(when.atoms().empty());
        for (const ConditionAtom* a : when.atoms())
            if (!a->arg.empty()) CHECK(m.arg(a->arg) != nullptr);
        ++seen;
    };
    for (const auto* list : {&cat.macros(), &cat.cycles()})
        for (const auto& m : *list) {
            for (const auto& st : m.action)
                if (!st.when.empty()) check(m, st.when);
            for (const auto& r : m.relations)
                if (!r.when.empty()) check(m, r.when);
            for (const auto& c : m.cautions) check(m, c.when);
        }
    CHECK(seen > 30);
    // The upper-limit return of the back-counterbore macros is the G17-only step OSP112 looks for.
    const ActionStep& st = cat.find("OG87C")->action.at(16);
    CHECK(st.when.required_plane() == 17);
    CHECK(st.when.mentions(ConditionAtom::Kind::MCode, 52));
    CHECK(st.when.mentions_value("PM", 52));
}

TEST_CASE("MacroSpec::arg: the index finds what comparing the names finds, for every name, alias and near miss") {
    const Catalog& cat = Catalog::builtin();
    // Every name an argument goes by, each with its case changed and a letter
    // added, removed or replaced, and names no argument has.
    auto probes = [](const MacroSpec& spec) {
        std::set<std::string> out{"", "P", "PZZZZZZZZ", "Q1", "PX1", "ZZ"};
        for (const auto& a : spec.args) {
            std::vector<std::string> names{a.name};
            names.insert(names.end(), a.aliases.begin(), a.aliases.end());
            for (const auto& n : names) {
                out.insert(n);
                std::string lower = n;
                for (char& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
                out.insert(lower);
                out.insert(n + "A");
                out.insert(n.substr(0, n.size() - 1));
                std::string other = n;
                other.back() = other.back() == 'Q' ? 'R' : 'Q';
                out.insert(other);
            }
        }
        return out;
    };
    size_t specs = 0, found = 0;
    auto check = [&](const MacroSpec& spec) {
        // The shipped names are all short: the index is made for every spec with arguments.
        REQUIRE(spec.arg_index.empty() == spec.args.empty());
        MacroSpec plain = spec;
        plain.arg_index.clear();  // arg() compares the names
        ++specs;
        for (const auto& n : probes(spec)) {
            INFO(spec.name << " " << n);
            CHECK(spec.arg(n) == (plain.arg(n) ? &spec.args[static_cast<size_t>(plain.arg(n) - plain.args.data())] : nullptr));
            if (spec.arg(n)) ++found;
        }
    };
    for (const auto& m : cat.macros()) check(m);
    for (const auto& c : cat.cycles()) check(c);
    CHECK(specs > 20);
    CHECK(found > 200);
}

TEST_CASE("catalog_expr: a text changed in place at the same address is parsed as it is now") {
    std::string text = "PR+1";
    const auto* a = catalog_expr(text);
    REQUIRE(a != nullptr);
    REQUIRE(a->size() == 2);
    CHECK(a->at(0).name == "PR");
    CHECK(catalog_expr(text) == a);  // asked again: the same terms
    const char* where = text.data();
    text[0] = 'Q';
    text[1] = 'Z';
    text[3] = '2';
    REQUIRE(text.data() == where);
    const auto* b = catalog_expr(text);
    REQUIRE(b != nullptr);
    CHECK(b != a);
    CHECK(b->at(0).name == "QZ");
    CHECK(b->at(1).number == 2);
    text = "PR+";  // not an expression
    CHECK(catalog_expr(text) == nullptr);
    CHECK(catalog_expr(std::string("PR+1")) == a);
}

TEST_CASE("relation sides: read once with the catalog, as the names and the roles give them") {
    const Catalog& cat = Catalog::builtin();
    size_t relations = 0, ordering = 0;
    auto check = [&](const MacroSpec& spec) {
        for (size_t i = 0; i < spec.relations.size(); ++i) {
            const Relation& r = spec.relations[i];
            INFO(spec.name << " " << r.left << " " << r.op << " " << r.right);
            const RelationSides* s = spec.sides(i);
            REQUIRE(s != nullptr);
            ++relations;
            const auto* left = catalog_expr(r.left);
            const auto* right = catalog_expr(r.right);
            REQUIRE((left && right));
            REQUIRE((s->left && s->right));
            REQUIRE(s->left->size() == left->size());
            REQUIRE(s->right->size() == right->size());
            REQUIRE(s->left_args.size() == left->size());
            REQUIRE(s->right_args.size() == right->size());
            bool cycle = false;
            for (const auto& [terms, args] : {std::pair{left, &s->left_args}, std::pair{right, &s->right_args}})
                for (size_t k = 0; k < terms->size(); ++k) {
                    const ExprTerm& t = (*terms)[k];
                    const ArgSpec* a = t.name.empty() ? nullptr : spec.arg(t.name);
                    CHECK((*args)[k] == (a ? static_cast<int>(a - spec.args.data()) : -1));
                    cycle = cycle || (a && a->role == ArgRole::Cycle);
                }
            CHECK(s->cycle_order == cycle);
            if (s->cycle_order) ++ordering;
        }
    };
    for (const auto& m : cat.macros()) check(m);
    for (const auto& c : cat.cycles()) check(c);
    CHECK(relations > 10);
    CHECK(ordering > 3);
    CHECK(ordering < relations);  // FA > F and the like are not orders on the cycle axis

    // A relation added after the catalog was read: none are served until they are made again.
    const MacroSpec* og87c = cat.find("OG87C");
    REQUIRE(og87c != nullptr);
    MacroSpec changed = *og87c;
    REQUIRE(changed.sides(0) != nullptr);
    changed.relations.push_back(Relation{"PR", ">", "PZ"});
    CHECK(changed.sides(0) == nullptr);
    const RelationSides made = relation_sides(changed.relations.back(), changed);
    CHECK(made.cycle_order);
    changed.index_args();
    REQUIRE(changed.sides(changed.relations.size() - 1) != nullptr);
    CHECK(changed.sides(changed.relations.size() - 1)->cycle_order);
    // A side that is not an expression orders nothing.
    changed.relations.push_back(Relation{"PR+", ">", "PZ"});
    CHECK_FALSE(relation_sides(changed.relations.back(), changed).cycle_order);
}
