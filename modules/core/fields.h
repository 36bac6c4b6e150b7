// core/fields: one description per settings struct, and what is generated from it.
// A settings struct T describes its members once, next to its definition, by an ADL function
//   template <class V> void fields(V& v, T& s) {
//       v("eps", s.eps, "solid-angle criterion ε");  // a member: JSON key, reference, doc
//       v("count", s.count, "points", Limits{1, 1e7}); // a number with the values it accepts
//       v.inlined(s.params);                          // a described member whose fields sit at
//                                                     // this level (flat JSON)
//       v.skip(s.threads, "results do not depend on it"); // a member that is no setting
//   }
// and an enum E its names by an ADL function
//   constexpr auto enumNames(E) { return std::array{std::pair{E::A, "a"}, ...}; }
// From that come: toJson / fromJson (symmetric by construction; enums by name; a missing key
// keeps the value already there, so older files read with today's defaults; an unknown key,
// a wrong type or an unknown enum name throws core::Error(file, 0, "path.key: expected …")),
// keyOf (a hash of every described member, for stage caches), limitProblem (why a numeric
// value is outside its Limits or, floating-point, not finite: the JSON reader throws it naming
// the path, the CLI flags refuse it naming the flag, so a setting has one range everywhere),
// fieldCount (the number of members of an aggregate: tests compare it with the description so a
// member added to the struct but not to its description fails) and forEachField (CLI flags,
// defaults tables).
#pragma once

#include "core/core.h"
#include "core/limits.h"
#include "core/text.h"

#include <glm/vec3.hpp>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <set>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>

namespace core {

// ---- enums --------------------------------------------------------------------------------
template <class E>
concept NamedEnum = std::is_enum_v<E> && requires(E e) {
    enumNames(e);
};

template <NamedEnum E> const char* nameOf(E e) {
    for (const auto& [v, n] : enumNames(E{}))
        if (v == e) return n;
    return "?";
}
// "a | b | c"
template <NamedEnum E> std::string enumNameList() {
    std::string out;
    for (const auto& [v, n] : enumNames(E{}))
        out += (out.empty() ? "" : " | ") + std::string(n);
    return out;
}
// Throws core::Error(file, 0, "where: unknown name 'x' (expected a | b)").
template <NamedEnum E>
E enumFromName(std::string_view name, const std::string& file, const std::string& where) {
    for (const auto& [v, n] : enumNames(E{}))
        if (name == n) return v;
    throw Error(file, 0,
                (where.empty() ? "" : where + ": ") + "unknown name '" + std::string(name) +
                    "' (expected " + enumNameList<E>() + ")");
}

// ---- limits -------------------------------------------------------------------------------
// core::Limits (core/limits.h): the range a description gives a numeric member.

// A setting's value as help texts and the README's defaults table show it: on/off, an enum's
// name, %g, a list or vector as "a,b,c", an empty string as "(none)".
template <class M> std::string defaultText(const M& m) {
    if constexpr (std::is_same_v<M, bool>) {
        return m ? "on" : "off";
    } else if constexpr (core::NamedEnum<M>) {
        return core::nameOf(m);
    } else if constexpr (std::is_floating_point_v<M>) {
        char b[32];
        std::snprintf(b, sizeof b, "%g", double(m));
        return b;
    } else if constexpr (std::is_arithmetic_v<M>) {
        return std::to_string(m);
    } else if constexpr (std::is_same_v<M, std::string>) {
        return m.empty() ? "(none)" : m;
    } else if constexpr (requires {
                             m.size();
                             m.begin();
                         }) { // a list: "a,b,c"
        std::string out;
        for (const auto& v : m)
            out += (out.empty() ? "" : ",") + defaultText(v);
        return out;
    } else {
        return defaultText(m.x) + "," + defaultText(m.y) + "," + defaultText(m.z);
    }
}

// An empty string when `value` is acceptable, else why not ("must be between 1 and 10, got 0").
template <class M> std::string limitProblem(const M& value, Limits lim) {
    if constexpr (std::is_same_v<M, glm::vec3> || std::is_same_v<M, glm::dvec3>) {
        for (int c = 0; c < 3; ++c)
            if (std::string p = limitProblem(double(value[c]), lim); !p.empty())
                return "component " + std::to_string(c) + " " + p;
        return "";
    } else if constexpr (std::is_arithmetic_v<M> && !std::is_same_v<M, bool>) {
        const double v = double(value);
        auto formatNumber = [](double x) { return core::formatNumber(x, 12); };
        if (std::is_floating_point_v<M> && !std::isfinite(value))
            return "must be a finite number, got " + formatNumber(v);
        if (v < lim.lo || v > lim.hi) {
            if (lim.hi == std::numeric_limits<double>::infinity())
                return "must be at least " + formatNumber(lim.lo) + ", got " + formatNumber(v);
            if (lim.lo == -std::numeric_limits<double>::infinity())
                return "must be at most " + formatNumber(lim.hi) + ", got " + formatNumber(v);
            return "must be between " + formatNumber(lim.lo) + " and " + formatNumber(lim.hi) +
                   ", got " + formatNumber(v);
        }
        return "";
    } else {
        return "";
    }
}

// ---- descriptions -------------------------------------------------------------------------
namespace detail {
struct NullVisitor {
    template <class T> void operator()(const char*, T&, const char*, Limits = {}) {}
    template <class T> void inlined(T&) {}
    template <class T> void skip(T&, const char*) {}
};
} // namespace detail

template <class T>
concept Described = requires(detail::NullVisitor& v, T& t) {
    fields(v, t);
};

template <class T, class F> void forEachField(T& s, F&& f, const std::string& prefix = "");
namespace detail {
template <class F> struct LeafVisitor {
    F& f;
    const std::string& prefix;
    template <class M> void operator()(const char* key, M& m, const char* doc, Limits lim = {}) {
        if constexpr (Described<M>)
            forEachField(m, f, prefix + key + ".");
        else if constexpr (std::is_invocable_v<F&, const std::string&, M&, const char*, Limits>)
            f(prefix + key, m, doc, lim);
        else
            f(prefix + key, m, doc);
    }
    template <class M> void inlined(M& m) { fields(*this, m); }
    template <class M> void skip(M&, const char*) {}
};
struct Counter {
    size_t n = 0;
    template <class M> void operator()(const char*, M&, const char*, Limits = {}) { ++n; }
    template <class M> void inlined(M&) { ++n; }
    template <class M> void skip(M&, const char*) { ++n; }
};
} // namespace detail
// Calls f(path, member&, doc) — or f(path, member&, doc, limits) where f takes them — for every
// described leaf member (nested structs flattened into
// "a.b" paths; inlined members at their parent's level). Skipped members are not visited.
template <class T, class F> void forEachField(T& s, F&& f, const std::string& prefix) {
    detail::LeafVisitor<std::remove_reference_t<F>> v{f, prefix};
    fields(v, s);
}

// The Limits the description of T gives the leaf member at `path` ("render.eps"); no limits
// for a member without them or a path T does not have.
template <class T> Limits limitsOf(const std::string& path) {
    T t{};
    Limits out;
    forEachField(t, [&](const std::string& p, auto&, const char*, Limits lim) {
        if (p == path) out = lim;
    });
    return out;
}

// Members an aggregate has (brace initialisation with as many convertible values as accepted).
namespace detail {
struct AnyMember {
    template <class T> operator T() const;
};
template <class T, class... A> consteval size_t aggregateArity() {
    if constexpr (requires { T{A{}..., AnyMember{}}; })
        return aggregateArity<T, A..., AnyMember>();
    else
        return sizeof...(A);
}
} // namespace detail
template <class T> consteval size_t fieldCount() {
    static_assert(std::is_aggregate_v<T>, "fieldCount needs an aggregate");
    return detail::aggregateArity<T>();
}
// Members the description of T names directly (fields, inlined structs and skipped ones).
template <Described T> size_t describedCount() {
    detail::Counter c;
    T t{};
    fields(c, t);
    return c.n;
}

// ---- JSON ---------------------------------------------------------------------------------
template <class T> nlohmann::json toJson(const T& value);

namespace detail {
struct JsonWriter {
    nlohmann::json& j;
    template <class M> void operator()(const char* key, M& m, const char*, Limits = {}) {
        j[key] = toJson(m);
    }
    template <class M> void inlined(M& m) { fields(*this, m); }
    template <class M> void skip(M&, const char*) {}
};
} // namespace detail

template <class T> nlohmann::json toJson(const T& value) {
    if constexpr (Described<T>) {
        nlohmann::json j = nlohmann::json::object();
        detail::JsonWriter w{j};
        fields(w, const_cast<T&>(value)); // the writer only reads
        return j;
    } else if constexpr (NamedEnum<T>) {
        return nameOf(value);
    } else if constexpr (std::is_same_v<T, glm::vec3> || std::is_same_v<T, glm::dvec3>) {
        return nlohmann::json::array({value.x, value.y, value.z});
    } else {
        return nlohmann::json(value);
    }
}

template <class T>
void fromJson(const nlohmann::json& j, T& out, const std::string& file, const std::string& path);

namespace detail {
struct JsonReader {
    const nlohmann::json& j;
    const std::string& file;
    const std::string& path;
    std::set<std::string> known;
    template <class M> void operator()(const char* key, M& m, const char*, Limits lim = {}) {
        known.insert(key);
        auto it = j.find(key);
        if (it == j.end()) return;
        fromJson(*it, m, file, path + "." + key);
        if (std::string p = limitProblem(m, lim); !p.empty())
            throw Error(file, 0, path + "." + key + ": " + p);
    }
    template <class M> void inlined(M& m) { fields(*this, m); }
    template <class M> void skip(M&, const char*) {}
};
} // namespace detail

// Reads `j` into `out`; see the header comment. `path` names `j` in messages
// ("settings.scene.render").
template <class T>
void fromJson(const nlohmann::json& j, T& out, const std::string& file, const std::string& path) {
    auto fail = [&](const std::string& what) { throw Error(file, 0, path + ": " + what); };
    if constexpr (Described<T>) {
        if (!j.is_object()) fail("expected an object");
        detail::JsonReader r{j, file, path, {}};
        fields(r, out);
        for (auto it = j.begin(); it != j.end(); ++it)
            if (!r.known.count(it.key()))
                throw Error(file, 0, path + "." + it.key() + ": unknown key");
    } else if constexpr (NamedEnum<T>) {
        // Integers are read too: format-1 captures stored some enums by their value.
        if (j.is_number_integer()) {
            for (const auto& [v, n] : enumNames(T{}))
                if (static_cast<long long>(v) == j.get<long long>()) {
                    out = v;
                    return;
                }
            fail("unknown value " + j.dump() + " (expected " + enumNameList<T>() + ")");
        }
        if (!j.is_string()) fail("expected one of " + enumNameList<T>());
        out = enumFromName<T>(j.get<std::string>(), file, path);
    } else if constexpr (std::is_same_v<T, glm::vec3> || std::is_same_v<T, glm::dvec3>) {
        if (!j.is_array() || j.size() != 3 || !j[0].is_number() || !j[1].is_number() ||
            !j[2].is_number())
            fail("expected an array of 3 numbers");
        out = T(j[0].get<double>(), j[1].get<double>(), j[2].get<double>());
        for (int c = 0; c < 3; ++c)
            if (!std::isfinite(out[c])) fail("number " + j[c].dump() + " out of range");
    } else if constexpr (std::is_same_v<T, bool>) {
        if (!j.is_boolean()) fail("expected true or false");
        out = j.get<bool>();
    } else if constexpr (std::is_integral_v<T>) {
        if (!j.is_number_integer()) fail("expected an integer");
        const bool fits = j.is_number_unsigned() ? std::in_range<T>(j.get<unsigned long long>())
                                                 : std::in_range<T>(j.get<long long>());
        if (!fits) fail("integer " + j.dump() + " out of range");
        out = j.get<T>();
    } else if constexpr (std::is_floating_point_v<T>) {
        if (!j.is_number()) fail("expected a number");
        const double v = j.get<double>();
        if (!std::isfinite(static_cast<T>(v))) fail("number " + j.dump() + " out of range");
        out = static_cast<T>(v);
    } else if constexpr (std::is_same_v<T, std::string>) {
        if (!j.is_string()) fail("expected a string");
        out = j.get<std::string>();
    } else {
        try {
            out = j.get<T>();
        } catch (const nlohmann::json::exception&) {
            fail("has the wrong type");
        }
    }
}
template <class T>
T fromJson(const nlohmann::json& j, const std::string& file, const std::string& path,
           T start = T{}) {
    fromJson(j, start, file, path);
    return start;
}

// ---- cache keys ---------------------------------------------------------------------------
// A hash ("fnv1a64:…") of every part: described structs with every described member, numbers
// exactly (floats with all their digits), anything else nlohmann::json can hold.
template <class... A> std::string keyOf(const A&... parts) {
    nlohmann::json j = nlohmann::json::array();
    (j.push_back(toJson(parts)), ...);
    return hashHex(j.dump());
}

} // namespace core
