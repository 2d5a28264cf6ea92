// Modal state of the control, computed once per block and shared by all rules.
//
// Every field is a `Val<T>`: either known (with a value) or unknown. The state
// at a block is the merge of the states flowing into it (textual predecessor,
// every jump to its sequence name, loop back edges); fields that differ become
// unknown. Rules never fire on an unknown field.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace osplint {

template <class T>
struct Val {
    bool known = false;
    T value{};

    static Val of(T v) { return Val{true, std::move(v)}; }
    static Val unknown() { return Val{}; }
    bool is(const T& v) const { return known && value == v; }
    // Merge: equal known values stay, anything else becomes unknown.
    void merge(const Val& o) {
        if (!known) return;
        if (!o.known || !(value == o.value)) *this = Val{};
    }
    friend bool operator==(const Val&, const Val&) = default;
};

enum class Units : uint8_t { Mm, Inch };
enum class Distance : uint8_t { Absolute, Incremental };  // G90 / G91
enum class Plane : uint8_t { G17, G18, G19 };
enum class CycleReturn : uint8_t { Initial, R };  // G98 / G99

// Axis letters of a plane: first and second positioning axes, cycle axis.
struct PlaneAxes {
    char first, second, cycle;
};
PlaneAxes plane_axes(Plane p);
const char* plane_name(Plane p);  // "G17"

// An active fixed cycle (G73..G89, G77, G78, G186, ... or a registered G-code
// macro cycle such as G114): its code and the values commanded so far.
struct ActiveCycle {
    int code = 0;                  // 81, 84, 114, ...
    std::string macro;             // "OG84L" when the cycle is a G-code macro, else empty
    uint32_t start_line = 0;       // block that started it
    Val<double> r, z;              // R and Z as commanded (meaning depends on G90/G91)
    Val<double> initial;           // cycle-axis position when the cycle was commanded
    friend bool operator==(const ActiveCycle&, const ActiveCycle&) = default;
};

// The macro of an open MODIN, with its arguments as commanded.
struct ActiveModin {
    std::string macro;  // "OG87C"
    uint32_t line = 0;  // the MODIN block
    // Argument name -> known numeric value (absent: not given or value unknown).
    std::map<std::string, double> values;
    std::vector<std::string> given;  // every argument name given on the MODIN line
    friend bool operator==(const ActiveModin&, const ActiveModin&) = default;
};

struct ModalState {
    Val<Plane> plane;
    Val<Distance> distance;
    Val<Units> units;
    Val<int> motion;  // 0, 1, 2, 3 or 60 (G60 is in the interpolation group on OSP)
    Val<double> work_offset;             // G15 H
    Val<bool> length_offset;             // G56 active (true) / G53 cancelled (false)
    Val<double> length_offset_h;         // H of G56
    Val<int> cutter_comp;                // 40, 41, 42
    Val<double> cutter_comp_d;           // D
    Val<double> g71_level;               // G71 Z..
    Val<int> return_level;               // 52, 53, 54
    Val<std::optional<ActiveCycle>> cycle;    // known none / known cycle / unknown
    Val<CycleReturn> cycle_return;            // G98 / G99
    Val<std::optional<ActiveModin>> modin;    // known none / known MODIN / unknown
    Val<int> spindle;                    // 3, 4, 5
    Val<double> spindle_speed;           // S
    Val<bool> coolant;                   // M7/M8/M12 on, M9 off
    Val<double> feed;                    // F
    Val<bool> overrides_disabled;        // after G114 until M204 (G80 leaves them off)
    Val<double> x, y, z;                 // tool-tip position in program coordinates
    // Variables with known constant values ("VC12", "PX", ...). A name that is
    // absent has an unknown value.
    std::map<std::string, double> vars;

    void merge(const ModalState& o);
    friend bool operator==(const ModalState&, const ModalState&) = default;

    Val<double> axis(char a) const {
        switch (a) {
            case 'X': return x;
            case 'Y': return y;
            case 'Z': return z;
            default: return {};
        }
    }
    Val<double>* axis_ref(char a) {
        switch (a) {
            case 'X': return &x;
            case 'Y': return &y;
            case 'Z': return &z;
            default: return nullptr;
        }
    }
};

std::string describe_state(const ModalState& s);  // one line for `osplint trace`

}  // namespace osplint
