#include "scene/xml_reader.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <system_error>

namespace whitted::xml {

namespace {

// Stray text is quoted in messages up to this many characters.
constexpr size_t kMaxQuotedText = 30;

// ---- Number parsing ----

enum class NumberKind { Finite, NotANumber, NotFinite, Overflow };

struct ParsedNumber {
    NumberKind kind;
    double value;
};

// std::from_chars does not take the leading '+' people may write.
std::string_view withoutPlus(std::string_view s) {
    if (s.size() > 1 && s[0] == '+' && s[1] != '-' && s[1] != '+') s.remove_prefix(1);
    return s;
}

// The whole of `text` as a decimal number. std::from_chars is locale-free and
// tells trailing garbage apart. Underflow reads as the (tiny or zero) value
// strtod gives.
ParsedNumber parseNumber(const std::string& text) {
    std::string_view s = withoutPlus(text);
    double value = 0;
    auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), value);
    if (s.empty() || end != s.data() + s.size() || ec == std::errc::invalid_argument)
        return {NumberKind::NotANumber, 0};
    if (ec == std::errc::result_out_of_range) {
        value = std::strtod(std::string(s).c_str(), nullptr);
        if (std::isinf(value)) return {NumberKind::Overflow, value};
    }
    if (!std::isfinite(value)) return {NumberKind::NotFinite, value};
    return {NumberKind::Finite, value};
}

// `label` names the number in messages: "<radius>", "attribute x of <position>".
double number(const Diagnostics& diag, const XMLNode* at, const std::string& label, const std::string& text,
              Range range) {
    ParsedNumber n = parseNumber(text);
    switch (n.kind) {
        case NumberKind::NotANumber:
            diag.fail(at, label + " must be a number, got " + inQuotes(text));
        case NumberKind::NotFinite:
            diag.fail(at, label + " must be a finite number, got " + inQuotes(text));
        case NumberKind::Overflow:
            diag.fail(at, label + " must be within ±1e6, got " + text);
        case NumberKind::Finite:
            break;
    }
    if (std::abs(n.value) > kMaxMagnitude) diag.fail(at, label + " must be within ±1e6, got " + text);
    if (!range.contains(n.value)) diag.fail(at, label + " must be " + range.describe() + ", got " + text);
    return n.value;
}

}  // namespace

// ---- Text helpers ----

std::string tag(std::string_view name) {
    return "<" + std::string(name) + ">";
}

std::string trimmed(std::string_view s) {
    auto isSpace = [](char c) { return std::isspace(static_cast<unsigned char>(c)) != 0; };
    while (!s.empty() && isSpace(s.front())) s.remove_prefix(1);
    while (!s.empty() && isSpace(s.back())) s.remove_suffix(1);
    return std::string(s);
}

std::string inQuotes(std::string_view text) {
    if (text.size() > kMaxQuotedText) return "\"" + std::string(text.substr(0, kMaxQuotedText)) + "...\"";
    return "\"" + std::string(text) + "\"";
}

std::string joined(const std::vector<std::string>& names, const std::string& lastSeparator) {
    std::string s;
    for (size_t i = 0; i < names.size(); ++i) {
        if (i > 0) s += i + 1 == names.size() ? lastSeparator : ", ";
        s += names[i];
    }
    return s;
}

std::string showBound(double v) {
    std::array<char, 32> buffer{};
    std::snprintf(buffer.data(), buffer.size(), "%g", v);
    return buffer.data();
}

std::string Range::describe() const {
    if (hi == kMaxMagnitude && !hiOpen) return (loOpen ? "> " : ">= ") + showBound(lo);
    return std::string("in ") + (loOpen ? "(" : "[") + showBound(lo) + ", " + showBound(hi) + (hiOpen ? ")" : "]");
}

// ---- Diagnostics ----

void Diagnostics::fail(const XMLNode* at, const std::string& message) const {
    throw SceneError(file_, at ? at->GetLineNum() : 0, message);
}

void Diagnostics::warn(const XMLNode* at, const std::string& message) const {
    warnings_->push_back(located(file_, at ? at->GetLineNum() : 0, message));
}

void Diagnostics::refuseAttributes(const XMLElement* e, std::string_view allowed) const {
    for (const tinyxml2::XMLAttribute* a = e->FirstAttribute(); a; a = a->Next())
        if (allowed.empty() || a->Name() != allowed)
            fail(e, "unknown attribute \"" + std::string(a->Name()) + "\" on " + tag(e->Name()) + "; " +
                        tag(e->Name()) +
                        (allowed.empty() ? " takes no attributes" : " takes only " + std::string(allowed)));
}

void Diagnostics::refuseText(const XMLText* text, const XMLElement* parent) const {
    std::string content = trimmed(text->Value());
    if (!content.empty()) fail(text, "unexpected text " + inQuotes(content) + " in " + tag(parent->Name()));
}

// ---- Element reader ----

ElementReader::ElementReader(const Diagnostics& diag, const XMLElement* element, const std::vector<ChildRule>& rules)
    : diag_(diag), element_(element) {
    for (const ChildRule& rule : rules) slots_.push_back({rule, {}, false});
    diag.refuseAttributes(element);
    for (const XMLNode* node = element->FirstChild(); node; node = node->NextSibling()) {
        if (const XMLText* text = node->ToText()) diag.refuseText(text, element);
        const XMLElement* child = node->ToElement();
        if (!child) continue;
        Slot* slot = find(child->Name());
        if (!slot)
            diag.fail(child,
                      "unknown element " + tag(child->Name()) + " in " + tag(element->Name()) + "; " + expected());
        if (!slot->rule.repeatable && !slot->elements.empty())
            diag.fail(child, "duplicate " + tag(child->Name()) + " in " + tag(element->Name()));
        slot->elements.push_back(child);
    }
}

const XMLElement* ElementReader::optional(std::string_view name) {
    Slot& slot = declared(name);
    slot.used = true;
    return slot.elements.empty() ? nullptr : slot.elements.front();
}

const XMLElement* ElementReader::required(std::string_view name) {
    const XMLElement* child = optional(name);
    if (!child) diag_.fail(element_, tag(element_->Name()) + " is missing " + tag(name));
    return child;
}

const std::vector<const XMLElement*>& ElementReader::all(std::string_view name) {
    Slot& slot = declared(name);
    slot.used = true;
    return slot.elements;
}

const XMLElement* ElementReader::firstUnused() const {
    for (const XMLElement* child = element_->FirstChildElement(); child; child = child->NextSiblingElement())
        if (!find(child->Name())->used) return child;
    return nullptr;
}

ElementReader::Slot* ElementReader::find(std::string_view name) {
    auto it = std::find_if(slots_.begin(), slots_.end(), [&](const Slot& s) { return s.rule.name == name; });
    return it == slots_.end() ? nullptr : &*it;
}

const ElementReader::Slot* ElementReader::find(std::string_view name) const {
    auto it = std::find_if(slots_.begin(), slots_.end(), [&](const Slot& s) { return s.rule.name == name; });
    return it == slots_.end() ? nullptr : &*it;
}

// Reading a name the rules do not list is a bug in the caller, not in the scene.
ElementReader::Slot& ElementReader::declared(std::string_view name) {
    Slot* slot = find(name);
    if (!slot) throw std::logic_error("scene loader reads undeclared <" + std::string(name) + ">");
    return *slot;
}

std::string ElementReader::expected() const {
    std::vector<std::string> names;
    for (const Slot& s : slots_) names.emplace_back(s.rule.name);
    if (names.size() == 1) return "expected " + names[0];
    return "expected one of: " + joined(names);
}

const XMLElement* laterOf(const XMLElement* a, const XMLElement* b) {
    for (const XMLElement* e = a; e; e = e->NextSiblingElement())
        if (e == b) return b;
    return a;
}

// ---- Values ----

std::string valueText(const Diagnostics& diag, const XMLElement* e, std::string_view attribute) {
    diag.refuseAttributes(e, attribute);
    std::string text;
    for (const XMLNode* node = e->FirstChild(); node; node = node->NextSibling()) {
        if (const XMLElement* child = node->ToElement())
            diag.fail(child, "unknown element " + tag(child->Name()) + " in " + tag(e->Name()) + "; " +
                                 tag(e->Name()) + " holds a value, not elements");
        if (const XMLText* part = node->ToText()) text += part->Value();
    }
    return trimmed(text);
}

double number(const Diagnostics& diag, const XMLElement* e, Range range) {
    return number(diag, e, tag(e->Name()), valueText(diag, e), range);
}

int integer(const Diagnostics& diag, const XMLElement* e, int lo, int hi) {
    std::string text = valueText(diag, e);
    std::string_view digits = withoutPlus(text);
    int value = 0;
    auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), value);
    if (digits.empty() || end != digits.data() + digits.size() || ec == std::errc::invalid_argument)
        diag.fail(e, tag(e->Name()) + " must be an integer, got " + inQuotes(text));
    if (ec == std::errc::result_out_of_range || value < lo || value > hi)
        diag.fail(e, tag(e->Name()) + " must be in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], got " +
                         text);
    return value;
}

bool boolean(const Diagnostics& diag, const XMLElement* e) {
    std::string text = valueText(diag, e);
    std::string lower = text;
    std::transform(lower.begin(), lower.end(), lower.begin(), [](unsigned char c) { return std::tolower(c); });
    if (lower == "true" || lower == "1") return true;
    if (lower == "false" || lower == "0") return false;
    diag.fail(e, tag(e->Name()) + " must be true or false, got " + inQuotes(text));
}

std::array<double, 4> components(const Diagnostics& diag, const XMLElement* e, const std::vector<Component>& wanted) {
    std::vector<std::string> names;
    for (const Component& c : wanted) names.emplace_back(c.name);
    std::array<double, 4> values{};

    if (e->FirstAttribute() && e->FirstChildElement())
        diag.fail(e, tag(e->Name()) + " mixes attributes and child elements; use one form");
    if (e->FirstAttribute()) {
        for (const tinyxml2::XMLAttribute* a = e->FirstAttribute(); a; a = a->Next())
            if (std::find(names.begin(), names.end(), a->Name()) == names.end())
                diag.fail(e, "unknown attribute \"" + std::string(a->Name()) + "\" on " + tag(e->Name()) +
                                 "; expected " + joined(names));
        for (const XMLNode* node = e->FirstChild(); node; node = node->NextSibling())
            if (const XMLText* text = node->ToText()) diag.refuseText(text, e);
        for (size_t i = 0; i < wanted.size(); ++i) {
            const Component& c = wanted[i];
            const char* text = e->Attribute(std::string(c.name).c_str());
            if (!text) {
                if (c.optional) continue;
                diag.fail(e, tag(e->Name()) + " is missing attribute \"" + std::string(c.name) + "\"");
            }
            values[i] =
                number(diag, e, "attribute " + std::string(c.name) + " of " + tag(e->Name()), trimmed(text), c.range);
        }
        return values;
    }

    std::vector<ChildRule> rules;
    for (const Component& c : wanted) rules.push_back({c.name});
    ElementReader children(diag, e, rules);
    for (size_t i = 0; i < wanted.size(); ++i) {
        const Component& c = wanted[i];
        const XMLElement* child = c.optional ? children.optional(c.name) : children.required(c.name);
        if (child)
            values[i] = number(diag, child, tag(c.name) + " of " + tag(e->Name()), valueText(diag, child), c.range);
    }
    return values;
}

glm::dvec3 vector(const Diagnostics& diag, const XMLElement* e, Range range) {
    auto v = components(diag, e, {{"x", range}, {"y", range}, {"z", range}});
    return {v[0], v[1], v[2]};
}

glm::dvec3 direction(const Diagnostics& diag, const XMLElement* e) {
    glm::dvec3 v = vector(diag, e);
    double length = glm::length(v);
    if (!(length > kMinLength)) diag.fail(e, tag(e->Name()) + " must not be the zero vector");
    return v / length;
}

glm::dvec3 colour(const Diagnostics& diag, const XMLElement* e, Range channel) {
    auto v = components(diag, e, {{"r", channel}, {"g", channel}, {"b", channel}, {"a", kUnitInterval, true}});
    return {v[0], v[1], v[2]};
}

}  // namespace whitted::xml
