// The XML reading machinery under the scene loader, the role pbrt's
// paramdict plays: placing errors and warnings at FILE:LINE, checking a
// container's children against the names allowed there (refusing unknown,
// repeated and unused elements), and reading values (numbers, integers,
// booleans, vectors, colours) with the range each may take. It knows no
// scene rule: which elements a scene has, and what they mean, is
// scene_loader.cpp's.
#pragma once

#include "scene/scene_error.h"

#include <glm/glm.hpp>
#include <tinyxml2.h>

#include <array>
#include <cmath>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace whitted::xml {

using tinyxml2::XMLElement;
using tinyxml2::XMLNode;
using tinyxml2::XMLText;

// Every number of the format is within ±kMaxMagnitude (scenes/README.md "Scene files").
inline constexpr double kMaxMagnitude = 1e6;
// Whether every coordinate of `v` is within ±kMaxMagnitude (false for NaN).
inline bool withinMagnitude(const glm::dvec3& v) {
    return std::abs(v.x) <= kMaxMagnitude && std::abs(v.y) <= kMaxMagnitude && std::abs(v.z) <= kMaxMagnitude;
}
// Below this length a direction (or the eye-to-window vector) counts as zero.
inline constexpr double kMinLength = 1e-12;

// ---- Text helpers ----

std::string tag(std::string_view name);  // "<name>"
std::string trimmed(std::string_view s);
// `text` in double quotes, cut with "..." past 30 characters.
std::string inQuotes(std::string_view text);
// "a, b, c"; with `lastSeparator` " or " the last pair reads "b or c".
std::string joined(const std::vector<std::string>& names, const std::string& lastSeparator = ", ");
// A range bound as people write it: 0.1, 10, 100000.
std::string showBound(double v);

// ---- Value ranges ----

// The values a number may take. Every number is also within ±kMaxMagnitude.
struct Range {
    double lo = -kMaxMagnitude;
    double hi = kMaxMagnitude;
    bool loOpen = false;
    bool hiOpen = false;

    bool contains(double v) const { return (loOpen ? v > lo : v >= lo) && (hiOpen ? v < hi : v <= hi); }

    // "> 0" or ">= 0" when the upper end is only the ±1e6 limit, else
    // "in [0, 1]" with open ends as parentheses.
    std::string describe() const;
};

inline constexpr Range kAnyValue{};
inline constexpr Range kPositive{0, kMaxMagnitude, true, false};
inline constexpr Range kNonNegative{0, kMaxMagnitude, false, false};
inline constexpr Range kUnitInterval{0, 1, false, false};  // coefficients, material colours, alpha

// ---- Diagnostics ----

// Errors and warnings of one file, each placed at the line of an XML node.
class Diagnostics {
public:
    Diagnostics(std::string file, std::vector<std::string>& warnings) : file_(std::move(file)), warnings_(&warnings) {}

    [[noreturn]] void fail(const XMLNode* at, const std::string& message) const;
    void warn(const XMLNode* at, const std::string& message) const;

    // Elements of the format carry no attributes except the compact vector
    // and colour form, which is checked on its own.
    void refuseAttributes(const XMLElement* e, std::string_view allowed = {}) const;
    void refuseText(const XMLText* text, const XMLElement* parent) const;

private:
    std::string file_;
    std::vector<std::string>* warnings_;
};

// ---- Element reader ----

// A child element name allowed in a container; `repeatable` ones may occur
// more than once.
struct ChildRule {
    std::string_view name;
    bool repeatable = false;
};

// The children of one container element, checked up front against the names
// the format allows there (Mitsuba's check_attributes): an unknown name, a
// repeated singular name, stray text or an attribute is refused, so a typo is
// never silently ignored. Reading a child marks it used; what was never read
// is what the caller did not expect (pbrt's ReportUnused), see firstUnused().
class ElementReader {
public:
    ElementReader(const Diagnostics& diag, const XMLElement* element, const std::vector<ChildRule>& rules);

    const XMLElement* element() const { return element_; }

    const XMLElement* optional(std::string_view name);
    const XMLElement* required(std::string_view name);
    const std::vector<const XMLElement*>& all(std::string_view name);

    // The first child, in document order, whose name was never read.
    const XMLElement* firstUnused() const;

private:
    struct Slot {
        ChildRule rule;
        std::vector<const XMLElement*> elements;
        bool used;
    };

    Slot* find(std::string_view name);
    const Slot* find(std::string_view name) const;
    Slot& declared(std::string_view name);
    std::string expected() const;

    const Diagnostics& diag_;
    const XMLElement* element_;
    std::vector<Slot> slots_;
};

// Of two siblings, the one that comes second in the document.
const XMLElement* laterOf(const XMLElement* a, const XMLElement* b);

// ---- Values ----
// Each reads one element and refuses, through `diag` at that element, what
// is not a value of the kind asked for.

// The text of a value element such as <radius>, trimmed and joined over
// its text nodes (a comment may sit inside); elements inside are refused.
// `attribute`, when given, is the one attribute the element may carry.
std::string valueText(const Diagnostics& diag, const XMLElement* e, std::string_view attribute = {});

double number(const Diagnostics& diag, const XMLElement* e, Range range = kAnyValue);
int integer(const Diagnostics& diag, const XMLElement* e, int lo, int hi);
// true, false, 1 or 0, in any case.
bool boolean(const Diagnostics& diag, const XMLElement* e);

// One number of a vector or colour.
struct Component {
    std::string_view name;
    Range range;
    bool optional = false;
};

// The numbers of a vector or colour, in the order of `wanted`, from
// one of two forms: attributes (<p x=".." y=".." z=".."/>) or child
// elements (<p><x>..</x>...</p>). A left-out optional component reads 0.
std::array<double, 4> components(const Diagnostics& diag, const XMLElement* e, const std::vector<Component>& wanted);

glm::dvec3 vector(const Diagnostics& diag, const XMLElement* e, Range range = kAnyValue);
// A vector that is not zero, made unit length.
glm::dvec3 direction(const Diagnostics& diag, const XMLElement* e);
// r, g, b within `channel`; the seed's alpha is accepted in [0, 1] and unused.
glm::dvec3 colour(const Diagnostics& diag, const XMLElement* e, Range channel);

}  // namespace whitted::xml
