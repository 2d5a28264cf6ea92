// The tree-sitter front end: the program model for representative blocks,
// errors at exact byte ranges, and hostile input.
#include <doctest/doctest.h>

#include <cmath>
#include <fstream>
#include <random>
#include <sstream>
#include <string>

#include "syntax/frontend.h"

using namespace osplint;

namespace {

ProgramFile parse(std::string text) { return parse_program_file("test.min", std::move(text)); }

std::string fixture(const std::string& name) {
    std::ifstream in(std::string(OSPLINT_SOURCE_DIR) + "/tests/frontend/" + name, std::ios::binary);
    REQUIRE_MESSAGE(in.good(), "missing fixture " << name);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

std::string_view slice(const ProgramFile& f, ByteRange r) {
    return std::string_view(f.source.text()).substr(r.begin, r.size());
}

size_t error_count(const ProgramFile& f) {
    size_t n = 0;
    for (const auto& b : f.blocks) n += b.errors.size();
    return n;
}

const ExprNode& node(const Block& b, ExprId id) {
    REQUIRE(b.expr(id) != nullptr);
    return *b.expr(id);
}

}  // namespace

TEST_CASE("glued words, signs and decimal points") {
    const auto f = parse("N1 G00X100Y50S425\nG0 X-.75 F.2 Z3. T121212 H01\n");
    REQUIRE(f.blocks.size() == 2);
    const Block& b = f.blocks[0];
    REQUIRE(b.sequence);
    CHECK(b.sequence->name == "N1");
    CHECK(b.sequence->range == ByteRange{0, 2});
    REQUIRE(b.words.size() == 4);
    CHECK(b.words[0].address == "G");
    CHECK(b.words[0].value_text == "00");
    CHECK(b.words[0].number == 0.0);
    CHECK(b.words[0].range == ByteRange{3, 6});
    CHECK(b.words[0].address_range == ByteRange{3, 4});
    CHECK(b.words[0].value_range == ByteRange{4, 6});
    CHECK_FALSE(b.words[0].equals);
    CHECK(b.words[1].address == "X");
    CHECK(b.words[1].number == 100.0);
    CHECK(b.words[3].address == "S");
    CHECK(b.words[3].number == 425.0);
    CHECK(b.has_code("G", 0));

    const Block& c = f.blocks[1];
    REQUIRE(c.words.size() == 6);
    const Word& x = c.words[1];
    CHECK(x.value_text == "-.75");
    CHECK(x.number == -0.75);
    const ExprNode& neg = node(c, x.value);
    CHECK(neg.kind == ExprKind::Unary);
    CHECK(neg.op == "-");
    REQUIRE(neg.children.size() == 1);
    CHECK(node(c, neg.children[0]).kind == ExprKind::Number);
    CHECK(node(c, neg.children[0]).number == 0.75);
    CHECK(slice(f, node(c, neg.children[0]).range) == ".75");
    CHECK(c.words[2].number == doctest::Approx(0.2));
    CHECK(c.words[3].number == 3.0);
    CHECK(c.words[4].number == 121212.0);
    CHECK(c.words[5].value_text == "01");
    CHECK(c.errors.empty());
}

TEST_CASE("lowercase code is upper-cased in the model") {
    const auto f = parse("otest\nn10 g1 x1.5\ncall ozagr pr=1\ngoto nstop\n");
    REQUIRE(f.blocks.size() == 4);
    CHECK(f.blocks[0].program_name->name == "OTEST");
    CHECK(f.blocks[1].sequence->name == "N10");
    CHECK(f.blocks[1].words[0].address == "G");
    REQUIRE(f.blocks[2].statements.size() == 1);
    CHECK(f.blocks[2].statements[0].name == "OZAGR");
    CHECK(f.blocks[2].words[0].address == "PR");
    CHECK(f.blocks[3].statements[0].name == "NSTOP");
    CHECK(error_count(f) == 0);
}

TEST_CASE("ADDR=expr on single- and multi-letter addresses") {
    const auto f = parse("G1 X=XPOS+8 Z=-2 FA=200 TG=01 HP=4\n");
    const Block& b = f.blocks[0];
    REQUIRE(b.words.size() == 6);
    const Word& x = b.words[1];
    CHECK(x.address == "X");
    CHECK(x.equals);
    CHECK(x.value_text == "XPOS+8");
    CHECK(x.value_range == ByteRange{5, 11});
    CHECK_FALSE(x.number.has_value());
    const ExprNode& sum = node(b, x.value);
    CHECK(sum.kind == ExprKind::Binary);
    CHECK(sum.op == "+");
    CHECK(node(b, sum.children[0]).kind == ExprKind::Variable);
    CHECK(node(b, sum.children[0]).text == "XPOS");
    CHECK(b.words[2].number == -2.0);  // Z=-2 is still a numeric literal
    CHECK(b.words[3].address == "FA");
    CHECK(b.words[3].equals);
    CHECK(b.words[3].number == 200.0);
    CHECK(b.words[3].address_range == ByteRange{17, 19});
    CHECK(b.words[4].address == "TG");
    CHECK(b.words[4].value_text == "01");
    CHECK(b.words[5].address == "HP");
    CHECK(b.assignments.empty());
}

TEST_CASE("assignments, several per block, even without separators") {
    const auto f = parse("VTOFX[16]=VTOFX[6]VTOFZ[16]=VTOFZ[6]-3.1(2ND OFFSET)\n");
    const Block& b = f.blocks[0];
    REQUIRE(b.assignments.size() == 2);
    const ExprNode& t0 = node(b, b.assignments[0].target);
    CHECK(t0.kind == ExprKind::Variable);
    CHECK(t0.text == "VTOFX");
    REQUIRE(t0.children.size() == 1);
    CHECK(node(b, t0.children[0]).number == 16.0);
    CHECK(b.assignments[0].range == ByteRange{0, 18});
    const ExprNode& v1 = node(b, b.assignments[1].value);
    CHECK(v1.kind == ExprKind::Binary);
    CHECK(v1.op == "-");
    CHECK(node(b, v1.children[1]).number == doctest::Approx(3.1));
    REQUIRE(b.comments.size() == 1);
    CHECK(slice(f, b.comments[0].range) == "(2ND OFFSET)");
    CHECK(b.words.empty());
    CHECK(b.errors.empty());
}

TEST_CASE("variables: common, lathe, system, indexed, locals") {
    const auto f = parse(
        "VC[CNTR] = EMPTY\n"
        "CNTR = PSRT\n"
        "V19=0\n"
        "VFST=#81H\n"
        "VTOHT [[VTLCN] , 10001]=VORD[002C]\n"
        "VUACM[1]='NO DATA \"PX\"'\n"
        "GDIA=5 TL2=0404\n");
    REQUIRE(f.blocks.size() == 7);
    {
        const Block& b = f.blocks[0];
        REQUIRE(b.assignments.size() == 1);
        const ExprNode& t = node(b, b.assignments[0].target);
        CHECK(t.text == "VC");
        REQUIRE(t.children.size() == 1);
        CHECK(node(b, t.children[0]).text == "CNTR");
        CHECK(node(b, b.assignments[0].value).kind == ExprKind::Empty);
    }
    {
        const Block& b = f.blocks[1];  // a plain local stays a word
        REQUIRE(b.words.size() == 1);
        CHECK(b.assignments.empty());
        CHECK(b.words[0].address == "CNTR");
        CHECK(b.words[0].equals);
        CHECK(node(b, b.words[0].value).text == "PSRT");
    }
    CHECK(node(f.blocks[2], f.blocks[2].assignments.at(0).target).text == "V19");
    {
        const Block& b = f.blocks[3];
        REQUIRE(b.assignments.size() == 1);
        const ExprNode& h = node(b, b.assignments[0].value);
        CHECK(h.kind == ExprKind::HexConst);
        CHECK(h.number == 0x81);
        CHECK(h.text == "#81H");
    }
    {
        const Block& b = f.blocks[4];
        REQUIRE(b.assignments.size() == 1);
        const ExprNode& t = node(b, b.assignments[0].target);
        CHECK(t.text == "VTOHT");
        REQUIRE(t.children.size() == 2);
        CHECK(node(b, t.children[0]).kind == ExprKind::Bracket);
        CHECK(node(b, t.children[1]).number == 10001.0);
        const ExprNode& v = node(b, b.assignments[0].value);
        REQUIRE(v.children.size() == 1);
        CHECK(node(b, v.children[0]).kind == ExprKind::HexConst);
        CHECK(node(b, v.children[0]).number == 0x2C);
    }
    CHECK(node(f.blocks[5], f.blocks[5].assignments.at(0).value).text == "NO DATA \"PX\"");
    REQUIRE(f.blocks[6].words.size() == 2);
    CHECK(f.blocks[6].words[0].address == "GDIA");
    CHECK(f.blocks[6].words[1].address == "TL2");
    CHECK(error_count(f) == 0);
}

TEST_CASE("expressions: precedence, functions, brackets") {
    const auto f = parse("VC1=1+2*SIN[30]\nIF [[VTLD3[VTLCN] AND 224] NE 0] NPT\nVC2=ATAN2[VC3,-1]\n");
    {
        const Block& b = f.blocks[0];
        const ExprNode& sum = node(b, b.assignments.at(0).value);
        CHECK(sum.op == "+");
        const ExprNode& prod = node(b, sum.children.at(1));
        CHECK(prod.op == "*");
        const ExprNode& sin = node(b, prod.children.at(1));
        CHECK(sin.kind == ExprKind::Function);
        CHECK(sin.text == "SIN");
        CHECK(node(b, sin.children.at(0)).number == 30.0);
    }
    {
        const Block& b = f.blocks[1];
        const Statement* st = b.statement(StmtKind::If);
        REQUIRE(st);
        const ExprNode& ne = node(b, st->expr);
        CHECK(ne.op == "NE");
        const ExprNode& br = node(b, ne.children.at(0));
        CHECK(br.kind == ExprKind::Bracket);
        CHECK(node(b, br.children.at(0)).op == "AND");
        CHECK(st->name == "NPT");
    }
    {
        const Block& b = f.blocks[2];
        const ExprNode& fn = node(b, b.assignments.at(0).value);
        CHECK(fn.text == "ATAN2");
        REQUIRE(fn.children.size() == 2);
        CHECK(node(b, fn.children[1]).kind == ExprKind::Unary);
    }
}

TEST_CASE("CALL and MODIN: name, repeat count and arguments") {
    const auto f = parse(
        "CALL OLAPX Q5 PX=20 PZ=-100 PK=.5\n"
        "CALL OO30 VFST=#81H PY=PY\n"
        "MODIN OINT1 PZ=-5\n"
        "MODOUT\n"
        "N100 RTS\n");
    {
        const Block& b = f.blocks[0];
        const Statement* call = b.statement(StmtKind::Call);
        REQUIRE(call);
        CHECK(call->name == "OLAPX");
        CHECK(call->name_range == ByteRange{5, 10});
        CHECK(call->keyword_range == ByteRange{0, 4});
        CHECK(call->range == ByteRange{0, 33});
        REQUIRE(b.words.size() == 4);
        CHECK(b.words[0].address == "Q");
        CHECK(b.words[0].number == 5.0);
        CHECK_FALSE(b.words[0].equals);
        CHECK(b.words[1].address == "PX");
        CHECK(b.words[1].equals);
        CHECK(b.words[2].number == -100.0);
        CHECK(b.words[3].number == 0.5);
    }
    {
        const Block& b = f.blocks[1];  // a system variable among the arguments is an argument
        REQUIRE(b.words.size() == 2);
        CHECK(b.assignments.empty());
        CHECK(b.words[0].address == "VFST");
        CHECK(node(b, b.words[0].value).kind == ExprKind::HexConst);
    }
    CHECK(f.blocks[2].statement(StmtKind::Modin)->name == "OINT1");
    CHECK(f.blocks[2].words.at(0).number == -5.0);
    CHECK(f.blocks[3].statement(StmtKind::Modout) != nullptr);
    CHECK(f.blocks[4].statement(StmtKind::Rts) != nullptr);
    CHECK(f.blocks[4].sequence->name == "N100");
}

TEST_CASE("IF, GOTO, WHILE, DO, END") {
    const auto f = parse(
        "NTC5 IF [PT NE EMPTY] NTC6\n"
        "IF[PA EQ EMPTY]NER04\n"
        "IF[V19 LT 5] GOTO NSTRT\n"
        "GOTO NSTOP\n"
        "WHILE [CNTR LE PEND] DO 1\n"
        "DO2\n"
        "END 1\n"
        "END\n");
    REQUIRE(f.blocks.size() == 8);
    const Statement* if0 = f.blocks[0].statement(StmtKind::If);
    REQUIRE(if0);
    CHECK(if0->name == "NTC6");
    CHECK(if0->name_range == ByteRange{22, 26});
    CHECK(if0->keyword_range == ByteRange{5, 7});
    CHECK(node(f.blocks[0], if0->expr).op == "NE");
    CHECK(f.blocks[0].sequence->name == "NTC5");
    CHECK(f.blocks[1].statement(StmtKind::If)->name == "NER04");
    CHECK(f.blocks[2].statement(StmtKind::If)->name == "NSTRT");
    CHECK(f.blocks[3].statement(StmtKind::Goto)->name == "NSTOP");
    const Statement* wh = f.blocks[4].statement(StmtKind::While);
    REQUIRE(wh);
    CHECK(wh->loop == 1);
    CHECK(node(f.blocks[4], wh->expr).op == "LE");
    CHECK(f.blocks[5].statement(StmtKind::Do)->loop == 2);
    CHECK(f.blocks[6].statement(StmtKind::End)->loop == 1);
    CHECK(f.blocks[7].statement(StmtKind::End)->loop == -1);
    CHECK(error_count(f) == 0);
}

TEST_CASE("N names: sequence names, jump targets inside blocks, NCYL/NOEX") {
    const auto f = parse(
        "NAT00 G81\n"
        "N10G0X5\n"
        "G85 N0207 D7\n"
        "G85 NAT3 D1\n"
        "NCYL G81 Z=ZPOS-2.6 R=ZPOS+3 M54\n"
        "NOEX G0 X1\n"
        "NEND\n");
    CHECK(f.blocks[0].sequence->name == "NAT00");
    CHECK(f.blocks[1].sequence->name == "N10");
    CHECK(f.blocks[1].words.size() == 2);
    {
        const Block& b = f.blocks[2];
        CHECK_FALSE(b.sequence);
        const Word* n = b.find("N");
        REQUIRE(n);
        CHECK(n->number == 207.0);
        CHECK(n->value_text == "0207");
        CHECK(n->range == ByteRange{22, 27});
    }
    {
        const Word* n = f.blocks[3].find("N");
        REQUIRE(n);
        CHECK(n->value_text == "AT3");
        CHECK_FALSE(n->number.has_value());
    }
    {
        const Block& b = f.blocks[4];
        CHECK_FALSE(b.sequence);
        REQUIRE(b.statement(StmtKind::Ncyl));
        CHECK(slice(f, b.statement(StmtKind::Ncyl)->keyword_range) == "NCYL");
        CHECK(b.has_code("G", 81));
        CHECK(b.has_code("M", 54));
        CHECK(b.find("Z")->value_text == "ZPOS-2.6");
    }
    CHECK(f.blocks[5].statement(StmtKind::Noex) != nullptr);
    CHECK(f.blocks[6].sequence->name == "NEND");
}

TEST_CASE("coordinate calculation keeps repeated addresses") {
    const auto f = parse("LAA X=XPOS Y=YPOS I25 I76 I25 J0\nBHC X0 Y0 I50 J0 K6\n");
    const Block& b = f.blocks[0];
    const Statement* laa = b.statement(StmtKind::CoordCalc);
    REQUIRE(laa);
    CHECK(laa->name == "LAA");
    REQUIRE(b.words.size() == 6);
    int is = 0;
    for (const auto& w : b.words) is += w.address == "I";
    CHECK(is == 3);
    CHECK(b.words[3].number == 76.0);
    CHECK(f.blocks[1].statement(StmtKind::CoordCalc)->name == "BHC");
}

TEST_CASE("mnemonics and free-form commands") {
    const auto f = parse(
        "MSG (TOOL BROKEN)\n"
        "DEF WORK\n"
        "PT LF,LC,[0,0],[80,80]\n"
        "END\n"
        "FWRITC MD1:X.TXT;A\n"
        "PUT 'A B'\n"
        "PT=5\n"
        "G56 HA\n");
    CHECK(f.blocks[0].statement(StmtKind::Mnemonic)->name == "MSG");
    CHECK(f.blocks[0].comments.size() == 1);
    CHECK(f.blocks[1].statement(StmtKind::Mnemonic)->name == "DEF");
    CHECK(f.blocks[2].statement(StmtKind::Mnemonic)->name == "PT");
    CHECK(f.blocks[3].statement(StmtKind::End)->loop == -1);
    CHECK(f.blocks[4].statement(StmtKind::Mnemonic)->name == "FWRITC");
    CHECK(f.blocks[5].statement(StmtKind::Mnemonic)->name == "PUT");
    CHECK(f.blocks[6].statements.empty());
    CHECK(f.blocks[6].words.at(0).address == "PT");
    const Word* h = f.blocks[7].find("H");
    REQUIRE(h);
    CHECK(h->value_text == "A");
    CHECK_FALSE(h->number.has_value());
    CHECK(error_count(f) == 0);
}

TEST_CASE("block delete before and after the sequence name") {
    const auto f = parse("/N10 M00 (START)\nN20 /M01\n/ GOTO NSTOP\nG0 X1\n");
    CHECK(f.blocks[0].block_delete);
    CHECK(f.blocks[0].block_delete_range == ByteRange{0, 1});
    CHECK(f.blocks[0].sequence->name == "N10");
    CHECK(f.blocks[1].block_delete);
    CHECK(f.blocks[1].block_delete_range == ByteRange{21, 22});
    CHECK(f.blocks[2].block_delete);
    CHECK(f.blocks[2].statement(StmtKind::Goto)->name == "NSTOP");
    CHECK_FALSE(f.blocks[3].block_delete);
}

TEST_CASE("one block per line: blank, comment-only, tape marks, CRLF") {
    const auto f = parse("$OKUMA.SSB%\r\n%\r\n\r\n(ONLY A COMMENT)\r\n  \tG0 X1\r\n%%");
    REQUIRE(f.blocks.size() == 6);
    CHECK(f.blocks[0].kind == LineKind::Header);
    CHECK(f.blocks[1].kind == LineKind::TapeMark);
    CHECK(f.blocks[2].kind == LineKind::Block);
    CHECK(f.blocks[2].is_empty());
    CHECK(f.blocks[3].is_empty());
    CHECK(f.blocks[3].comments.size() == 1);
    CHECK(f.blocks[4].line == 5);
    CHECK(f.blocks[4].line_start == 36);
    CHECK(f.blocks[4].range == ByteRange{36, 44});  // without "\r\n"
    CHECK(f.blocks[4].words.size() == 2);
    CHECK(f.blocks[5].kind == LineKind::TapeMark);
    CHECK(error_count(f) == 0);

    // A final newline does not add a block; lone CRs end lines too.
    CHECK(parse("G0\nG1\n").blocks.size() == 2);
    const auto cr = parse("G0\rG1\r\rM30");
    REQUIRE(cr.blocks.size() == 4);
    CHECK(cr.blocks[1].words.at(0).number == 1.0);
    CHECK(cr.blocks[3].words.at(0).number == 30.0);
}

TEST_CASE("program names and split_programs") {
    const auto f = parse_program_file("multi.ssb", fixture("multi.ssb"));
    REQUIRE(f.blocks.size() == 11);
    REQUIRE(f.programs.size() == 2);
    // The header and the comment before the first name belong to the first program.
    CHECK(f.programs[0].name == "OSTRT");
    CHECK(f.programs[0].first_block == 0);
    CHECK(f.programs[0].end_block == 7);
    CHECK(slice(f, f.programs[0].name_range) == "OSTRT");
    CHECK(f.programs[1].name == "OTBOX");
    CHECK(f.programs[1].first_block == 7);
    CHECK(f.programs[1].end_block == 11);
    CHECK(f.blocks[7].comments.size() == 1);  // OTBOX  (BOX)
    CHECK(error_count(f) == 0);

    const auto unnamed = parse("G0 X1\nM30\nOSUB\nRTS\n");
    REQUIRE(unnamed.programs.size() == 2);
    CHECK(unnamed.programs[0].name.empty());
    CHECK(unnamed.programs[0].end_block == 2);
    CHECK(unnamed.programs[1].name == "OSUB");

    const auto names = parse("OTC  (G116)\nOPOP(BAR PULL)\nOG116 M132 M329\nOG=1\n");
    REQUIRE(names.programs.size() == 3);
    CHECK(names.programs[2].name == "OG116");
    CHECK(names.blocks[2].words.size() == 2);
    CHECK_FALSE(names.blocks[3].program_name);  // OG=1 is an assignment
    CHECK(split_programs({}).empty());
}

TEST_CASE("the OEX01 example program from the macro manual parses cleanly") {
    const auto f = parse_program_file("oex01.min", fixture("oex01.min"));
    CHECK(error_count(f) == 0);
    REQUIRE(f.programs.size() == 1);
    CHECK(f.programs[0].name == "OEX01");
    int calls = 0;
    for (const auto& b : f.blocks)
        if (const Statement* s = b.statement(StmtKind::Call)) calls += s->name == "OLAPX" || s->name == "OLAPY";
    CHECK(calls == 4);
    CHECK(f.blocks.back().has_code("M", 2));
}

TEST_CASE("Shift-JIS comments keep their exact byte ranges") {
    const auto f = parse_program_file("sjis.min", fixture("sjis.min"));
    CHECK(error_count(f) == 0);
    REQUIRE(f.blocks.size() == 3);
    REQUIRE(f.blocks[0].comments.size() == 1);
    CHECK(f.blocks[0].comments[0].range == ByteRange{6, 16});
    CHECK(decode_for_display(slice(f, f.blocks[0].comments[0].range)) ==
          "(\xE5\x8A\xA0\xE5\xB7\xA5\xE3\x80\x80\xE3\x82\xBD)");
    REQUIRE(f.blocks[1].words.size() == 3);
    CHECK(f.blocks[1].words[2].address == "Y");
}

TEST_CASE("syntax errors sit at exact byte ranges and the next line still parses") {
    const std::string text =
        "G01 X=[1+ Y5\n"   // 0
        "G02 X5\n"         // 13
        "GOTO\n"           // 20
        "CALL 123\n"       // 25
        "X=SIN[1\n"        // 34
        "G1 X5 @ Y6\n"     // 42
        "GO1 X5\n"         // 53
        "(UNCLOSED\n"      // 60
        "VUACM[1]='ABC\n"  // 70
        "M30\n";           // 84
    const auto f = parse(text);
    REQUIRE(f.blocks.size() == 10);

    REQUIRE(f.blocks[0].errors.size() == 1);
    CHECK(f.blocks[0].errors[0].range == ByteRange{10, 12});  // at `Y5`, where the operand is missing
    CHECK(f.blocks[0].errors[0].message.find("expected an operand after '+'") != std::string::npos);
    CHECK(f.blocks[0].find("Y") != nullptr);  // resumed after the error

    CHECK(f.blocks[1].errors.empty());
    CHECK(f.blocks[1].words.size() == 2);

    REQUIRE(f.blocks[2].errors.size() == 1);
    CHECK(f.blocks[2].errors[0].range == ByteRange{24, 24});  // the end of the line
    CHECK(f.blocks[2].errors[0].message.find("expected a sequence name after GOTO") != std::string::npos);

    REQUIRE(f.blocks[3].errors.size() == 1);
    CHECK(f.blocks[3].errors[0].range == ByteRange{30, 33});
    CHECK(f.blocks[3].errors[0].message.find("expected a program name") != std::string::npos);

    REQUIRE(f.blocks[4].errors.size() == 1);
    CHECK(f.blocks[4].errors[0].range == ByteRange{41, 41});
    CHECK(f.blocks[4].errors[0].message == "expected ']'");

    REQUIRE(f.blocks[5].errors.size() == 1);
    CHECK(f.blocks[5].errors[0].range == ByteRange{48, 49});
    CHECK(f.blocks[5].errors[0].message == "unexpected '@'");
    CHECK(f.blocks[5].words.size() == 3);

    REQUIRE(f.blocks[6].errors.size() == 1);
    CHECK(f.blocks[6].errors[0].range == ByteRange{53, 59});
    CHECK(f.blocks[6].errors[0].message.find("unknown command 'GO1'") != std::string::npos);

    REQUIRE(f.blocks[7].errors.size() == 1);
    CHECK(f.blocks[7].errors[0].message.find("expected ')'") != std::string::npos);
    CHECK(f.blocks[7].comments.size() == 1);

    REQUIRE(f.blocks[8].errors.size() == 1);
    CHECK(f.blocks[8].errors[0].range == ByteRange{79, 83});  // from the opening quote
    CHECK(f.blocks[8].errors[0].message.find("unterminated string") != std::string::npos);

    CHECK(f.blocks[9].errors.empty());
    CHECK(f.blocks[9].has_code("M", 30));
}

TEST_CASE("an error starts at the first character that cannot continue the block") {
    struct Case {
        const char* line;
        uint32_t column;  // 0-based byte offset in the line
        const char* message;
    };
    const Case cases[] = {
        {"G0 G90 X10..5 Y0", 11, "unexpected '.5'"},
        {"S15O0 M3", 3, "O is a program name only at the start of a line"},
        {"G1 Z-1-.5 F100", 6, "unexpected '-'"},
        {"CALL PX=70. PY=0", 5, "expected a program name (O...) after CALL"},
        {"MODIN 0G87K PR=5.", 6, "expected a program name (O...) after MODIN"},
        {"IF [VC1 = 2] NSKIP", 8, "expected ']'"},
        {"IF [VC1 EQ 1 NSKIP", 13, "expected ']' before 'NSKIP'"},
        {"WHILE [CNTR LE PEND] DO", 23, "expected a loop number after DO"},
        {"G1 X SDIA-3. F.2", 5, "expected a number or '=' after 'X'"},
        {"VC4=VC2**3", 8, "after '*'"},
        {"G0 G90 X=XPOS] Y=YPOS", 13, "unexpected ']'"},
        {")S1500 M3", 0, "unexpected ')'"},
        {"G0 Z100. M9;", 11, "unexpected ';'"},
        {"N20 GOTO", 8, "expected a sequence name after GOTO"},
    };
    for (const Case& k : cases) {
        CAPTURE(k.line);
        const auto f = parse(std::string(k.line) + "\nG1 X1\n");
        REQUIRE(f.blocks.size() == 2);
        REQUIRE_FALSE(f.blocks[0].errors.empty());
        CHECK(f.blocks[0].errors[0].range.begin == k.column);
        CHECK(f.blocks[0].errors[0].message.find(k.message) != std::string::npos);
        CHECK_FALSE(f.blocks[0].block_delete);
        CHECK(f.blocks[1].errors.empty());
    }
}

TEST_CASE("consecutive bad lines keep one error each") {
    const auto f = parse("N1 IF [PX EQ 1] 10\nIF PX EQ 1 N10\nN3 G1 X1\n");
    REQUIRE(f.blocks.size() == 3);
    REQUIRE(f.blocks[0].errors.size() == 1);
    CHECK(f.blocks[0].errors[0].range.end <= f.blocks[0].range.end);
    CHECK(f.blocks[0].sequence->name == "N1");
    REQUIRE(f.blocks[1].errors.size() == 1);
    CHECK(f.blocks[1].errors[0].range == ByteRange{22, 33});  // from `PX` to the line end
    CHECK(f.blocks[1].errors[0].message.find("expected '[' after IF") != std::string::npos);
    CHECK(f.blocks[2].errors.empty());
    CHECK(f.blocks[2].sequence->name == "N3");
}

TEST_CASE("hostile input never crashes") {
    SUBCASE("empty file") {
        const auto f = parse("");
        CHECK(f.blocks.empty());
        CHECK(f.programs.empty());
    }
    SUBCASE("NUL bytes are errors on their line") {
        const auto f = parse(std::string("G0\0X1\nG1\n", 9));
        REQUIRE(f.blocks.size() == 2);
        CHECK_FALSE(f.blocks[0].errors.empty());
        CHECK(f.blocks[0].errors[0].message.find("0x00") != std::string::npos);
        CHECK(f.blocks[1].errors.empty());
    }
    SUBCASE("binary data") {
        std::mt19937 rng(42);
        std::string data(1 << 16, '\0');
        for (auto& c : data) c = static_cast<char>(rng() & 0xFF);
        const auto f = parse(data);
        CHECK_FALSE(f.blocks.empty());
        CHECK(error_count(f) > 0);
        for (const auto& b : f.blocks)
            for (const auto& e : b.errors) {
                CHECK(e.range.begin >= b.range.begin);
                CHECK(e.range.end <= b.range.end);
            }
    }
    SUBCASE("2 MB comment") {
        const auto f = parse("G0 (" + std::string(2 << 20, 'A') + ")\nG1\n");
        REQUIRE(f.blocks.size() == 2);
        CHECK(f.blocks[0].comments.at(0).range.size() == (2u << 20) + 2);
        CHECK(error_count(f) == 0);
    }
    SUBCASE("400,000-digit number: too large for a value, an error, no infinity") {
        const auto f = parse("G0 X" + std::string(400000, '9') + "\nY." + std::string(400000, '0') + "1\nZ0." +
                             std::string(400000, '0') + "1\n");
        REQUIRE(f.blocks.size() == 3);
        REQUIRE(f.blocks[0].words.size() == 2);
        CHECK_FALSE(f.blocks[0].words[1].number.has_value());
        REQUIRE(f.blocks[0].expr(f.blocks[0].words[1].value));
        CHECK(f.blocks[0].expr(f.blocks[0].words[1].value)->kind == ExprKind::Error);
        REQUIRE(f.blocks[0].errors.size() == 1);
        CHECK(f.blocks[0].errors[0].message ==
              "the number 999999999999...99999999 (400000 digits) is too large to be read as a value");
        CHECK(f.blocks[0].errors[0].range.size() == 400000);
        // Many zeros after the point: 0, as near as a double gets.
        CHECK(f.blocks[1].words.at(0).number == 0.0);
        CHECK(f.blocks[2].words.at(0).number == 0.0);
        CHECK(f.blocks[1].errors.empty());
        CHECK(f.blocks[2].errors.empty());
    }
    SUBCASE("the largest literals a double holds, and the smallest it does not") {
        const std::string fits(308, '9');   // 1e308 - 1
        const std::string over(309, '9');   // above DBL_MAX (1.8e308)
        for (const std::string& line :
             {"X-" + over, "X=" + over + "+1", "VC1=[" + over + " GT 1]", "G85 N" + over, "DO " + over,
              "VC2=#" + std::string(300, 'F') + "H", "IF [VC1 EQ " + over + "] NA"}) {
            CAPTURE(line.substr(0, 12));
            const auto f = parse(line + "\n");
            REQUIRE(f.blocks.size() == 1);
            REQUIRE_FALSE(f.blocks[0].errors.empty());
            CHECK(f.blocks[0].errors[0].message.find("is too large to be read as a value") != std::string::npos);
            for (const auto& w : f.blocks[0].words)
                if (w.value_text.size() > 300) CHECK_FALSE(w.number.has_value());
            for (const auto& e : f.blocks[0].exprs)
                if (e.kind == ExprKind::Number || e.kind == ExprKind::HexConst) CHECK(std::isfinite(e.number));
        }
        const auto f = parse("X-" + fits + "\n");
        CHECK(error_count(f) == 0);
        REQUIRE(f.blocks[0].words.at(0).number.has_value());
        CHECK(*f.blocks[0].words[0].number < -9e307);
    }
    SUBCASE("invalid UTF-8") {
        const auto f = parse("G0 (\xFF\xFE\xC3\x28)\nX\xC3\xA9=1\nG1\n");
        REQUIRE(f.blocks.size() == 3);
        CHECK(f.blocks[0].errors.empty());
        CHECK_FALSE(f.blocks[1].errors.empty());
        CHECK(f.blocks[2].errors.empty());
    }
    SUBCASE("20,000 nested brackets") {
        const std::string deep = "G0\nX=" + std::string(20000, '[') + "1" + std::string(20000, ']') + "\nG1\n";
        const auto f = parse(deep);
        REQUIRE(f.blocks.size() == 3);
        REQUIRE(f.blocks[1].errors.size() == 1);
        CHECK(f.blocks[1].errors[0].message == "expression nested too deeply");
        CHECK(f.blocks[2].errors.empty());
        CHECK(f.blocks[2].has_code("G", 1));
    }
    SUBCASE("70,000 unclosed brackets: not handed to tree-sitter, which fails on them") {
        for (const std::string head : {"X=", "IF ", "VC1=SIN", "VC1=VC"}) {
            const std::string deep = "G0\n" + head + std::string(70000, '[') + "\nG1\n";
            const auto f = parse(deep);
            REQUIRE(f.blocks.size() == 3);
            REQUIRE(f.blocks[1].errors.size() == 1);
            CHECK(f.blocks[1].errors[0].message == "expression nested too deeply");
            CHECK(f.blocks[2].has_code("G", 1));
        }
    }
    SUBCASE("70,000 signs without an operand") {
        const auto f = parse("VC1=" + std::string(70000, '-') + "\nG1\n");
        REQUIRE(f.blocks.size() == 2);
        REQUIRE(f.blocks[0].errors.size() == 1);
        CHECK(f.blocks[0].errors[0].message == "expression nested too deeply");
        CHECK(f.blocks[1].has_code("G", 1));
    }
    SUBCASE("a long run of ] , or = after an expression is read only a little past the error") {
        for (const char c : {']', ',', '='}) {
            const std::string line = "VC1=1" + std::string(32000, c);
            const auto f = parse(line + "\nG1\n");
            REQUIRE(f.blocks.size() == 2);
            const auto& errors = f.blocks[0].errors;
            REQUIRE(errors.size() == 2);
            CHECK(errors[0].range.begin == 5);
            const uint32_t cut = 5 + 64;
            CHECK(errors[1].range.begin == cut);
            CHECK(errors[1].range.end == line.size());
            CHECK(errors[1].message ==
                  "the line is not read further: " + std::to_string(line.size() - cut) +
                      " more characters after a syntax error");
            CHECK(f.blocks[1].has_code("G", 1));
        }
    }
    SUBCASE("20,000 unclosed brackets") {
        const std::string deep = "G0\nX=" + std::string(20000, '[') + "1\nG1\nG2 X5\n";
        const auto f = parse(deep);
        REQUIRE(f.blocks.size() == 4);
        CHECK(f.blocks[0].errors.empty());
        CHECK_FALSE(f.blocks[1].errors.empty());
        CHECK(f.blocks[2].errors.empty());
        CHECK(f.blocks[3].find("X") != nullptr);
    }
}
