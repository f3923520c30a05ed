#pragma once

// The text names of an enum class as one table: to_string (name) and its inverse (parse) are one lookup over the
// table for every enum, instead of a switch and a loop written per enum. The same table maps an enum to another
// type (enum_map: a core enum to its IDL twin, and back with find).
//
// What the hand-written switch had from -Wswitch, the table has at compile time, and more: a constexpr table must
// name every enumerator exactly once. The number of enumerators is taken from the enum itself (a template argument
// that is an enumerator is spelt by its name in __PRETTY_FUNCTION__, any other value as a cast "(E)7": GCC and
// Clang, the technique of magic_enum), so an enumerator added anywhere in the enum without a name is a compile
// error, and so is a name given twice or to a value that is no enumerator (a throw reached while a constexpr
// variable is initialised is a compile error). Enumerators are looked for among the values 0 .. 63.
//
//   constexpr auto kNames = io::enum_names<Colour>({{Colour::red, "red"}, {Colour::green, "green"}});
//   kNames.name(c, "?");            // "?" for a value that is no enumerator (a cast)
//   kNames.parse("green");          // std::optional<Colour>
//
// Std only (header-only, in causal_io_time's include folder): every library may use it.

#include <array>
#include <cstddef>
#include <optional>
#include <stdexcept>
#include <string_view>
#include <type_traits>
#include <utility>

namespace causal::io {

// One enumerator and what it maps to (its text name in an EnumNames).
template <class E, class T>
struct EnumEntry {
  E value;
  T to;
};
template <class E>
using EnumName = EnumEntry<E, const char*>;

namespace detail {

constexpr int kEnumProbe = 64;

// True when V is a named enumerator of E.
template <class E, E V>
constexpr bool is_enumerator() {
  constexpr std::string_view signature = __PRETTY_FUNCTION__;
  constexpr std::size_t at = signature.rfind("V = ");
  static_assert(at != std::string_view::npos, "enum_names.hpp: unknown __PRETTY_FUNCTION__ layout");
  constexpr char first = signature[at + 4];
  return first != '(' && first != '-' && !(first >= '0' && first <= '9');
}

template <class E, int... I>
constexpr std::array<bool, sizeof...(I)> enumerator_map(std::integer_sequence<int, I...>) {
  return {is_enumerator<E, static_cast<E>(I)>()...};
}

// enumerators<E>()[v]: the value v is a named enumerator of E.
template <class E>
constexpr std::array<bool, kEnumProbe> enumerators() {
  return enumerator_map<E>(std::make_integer_sequence<int, kEnumProbe>());
}

template <class E>
constexpr std::size_t enumerator_count() {
  std::size_t n = 0;
  for (const bool named : enumerators<E>()) n += named ? 1 : 0;
  return n;
}

}  // namespace detail

// Every enumerator of E mapped to one T (a name, another enum's value, ...), checked as above.
template <class E, class T, std::size_t N>
class EnumMap {
  static_assert(std::is_enum_v<E> && !std::is_convertible_v<E, int>, "EnumNames: E must be an enum class");
  static_assert(detail::enumerator_count<E>() == N, "EnumNames: the list must name every enumerator of E");

 public:
  constexpr explicit EnumMap(const EnumEntry<E, T> (&entries)[N]) : entries_{} {
    constexpr std::array<bool, detail::kEnumProbe> named = detail::enumerators<E>();
    std::array<bool, detail::kEnumProbe> seen{};
    for (std::size_t i = 0; i < N; ++i) {
      const auto v = static_cast<long long>(entries[i].value);
      if (v < 0 || v >= detail::kEnumProbe || !named[static_cast<std::size_t>(v)]) {
        throw std::logic_error("EnumNames: a name for a value that is no enumerator");
      }
      if (seen[static_cast<std::size_t>(v)]) throw std::logic_error("EnumNames: an enumerator named twice");
      seen[static_cast<std::size_t>(v)] = true;
      entries_[i] = entries[i];
    }
  }

  // What `value` maps to, or `other` for a value that is no enumerator (a cast).
  T at(E value, T other) const {
    for (const EnumEntry<E, T>& e : entries_) {
      if (e.value == value) return e.to;
    }
    return other;
  }

  // The enumerator that maps to `to` (the first, if several do), if any. Names compare as text.
  template <class U>
  std::optional<E> find(const U& to) const {
    for (const EnumEntry<E, T>& e : entries_) {
      if (same(e.to, to)) return e.value;
    }
    return std::nullopt;
  }

 private:
  template <class U>
  static bool same(const T& mine, const U& theirs) {
    if constexpr (std::is_same_v<T, const char*>) {
      return std::string_view(mine) == std::string_view(theirs);
    } else {
      return mine == theirs;
    }
  }

  std::array<EnumEntry<E, T>, N> entries_;
};

// The text names of E: name (to_string) and parse (its exact inverse).
template <class E, std::size_t N>
class EnumNames : public EnumMap<E, const char*, N> {
 public:
  using EnumMap<E, const char*, N>::EnumMap;

  // The name of `value`, or `other` for a value that is no enumerator (a cast).
  const char* name(E value, const char* other) const { return this->at(value, other); }

  // The enumerator named exactly `text`, if any.
  std::optional<E> parse(std::string_view text) const { return this->find(text); }
};

// io::enum_names<E>({{E::a, "a"}, ...}): the table, its size from the list.
template <class E, std::size_t N>
constexpr EnumNames<E, N> enum_names(const EnumName<E> (&entries)[N]) {
  return EnumNames<E, N>(entries);
}

// io::enum_map<E, T>({{E::a, T::x}, ...}): every enumerator of E mapped to a T.
template <class E, class T, std::size_t N>
constexpr EnumMap<E, T, N> enum_map(const EnumEntry<E, T> (&entries)[N]) {
  return EnumMap<E, T, N>(entries);
}

}  // namespace causal::io
