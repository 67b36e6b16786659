// One field list per estimate: from it come both the replay CSV columns and the DDS sample, so the two cannot
// drift apart. A field that only one side carries says so where it is declared.
#pragma once

#include <array>
#include <functional>
#include <string>
#include <vector>

#include "csv.hpp"

namespace windfdi {

/// One field of an estimate: its CSV columns (none: DDS only), how its values are written as text, and how it
/// is put into the IDL sample (empty: CSV only).
template <class Estimate, class Idl>
struct EstimateField {
  std::vector<std::string> columns;
  std::function<void(const Estimate&, std::vector<std::string>&)> text;
  std::function<void(const Estimate&, Idl&)> put;
};

template <class Estimate, class Idl>
using EstimateFields = std::vector<EstimateField<Estimate, Idl>>;

/// The CSV columns of a field list, in order (after `t` and `turbine_id`).
template <class Estimate, class Idl>
std::vector<std::string> csv_columns(const EstimateFields<Estimate, Idl>& fields) {
  std::vector<std::string> out;
  for (const auto& f : fields) out.insert(out.end(), f.columns.begin(), f.columns.end());
  return out;
}

/// One text per CSV column of `e`.
template <class Estimate, class Idl>
void csv_values(const EstimateFields<Estimate, Idl>& fields, const Estimate& e,
                std::vector<std::string>& out) {
  out.clear();
  for (const auto& f : fields)
    if (f.text) f.text(e, out);
}

/// The IDL sample of `e` (the caller sets the time and the turbine id).
template <class Estimate, class Idl>
void put_fields(const EstimateFields<Estimate, Idl>& fields, const Estimate& e, Idl& out) {
  for (const auto& f : fields)
    if (f.put) f.put(e, out);
}

// Field makers. `get` reads the estimate; `put` writes the IDL sample (both lambdas, as the IDL accessors
// are overloaded and cannot be named by pointer).

/// A number in both.
template <class Estimate, class Idl, class Get, class Put>
EstimateField<Estimate, Idl> number_field(const std::string& column, Get get, Put put) {
  return {{column},
          [get](const Estimate& e, std::vector<std::string>& v) { v.push_back(format_number(get(e))); },
          [get, put](const Estimate& e, Idl& out) { put(out, get(e)); }};
}

/// A flag (CSV 1/0) in both.
template <class Estimate, class Idl, class Get, class Put>
EstimateField<Estimate, Idl> flag_field(const std::string& column, Get get, Put put) {
  return {{column},
          [get](const Estimate& e, std::vector<std::string>& v) { v.push_back(get(e) ? "1" : "0"); },
          [get, put](const Estimate& e, Idl& out) { put(out, get(e)); }};
}

/// One value per blade: columns `<name>_1..3`; `get` returns an array of 3, `put(out, array)` stores it;
/// `to_text` formats one value.
template <class Estimate, class Idl, class Get, class Put, class ToText>
EstimateField<Estimate, Idl> per_blade_field(const std::string& name, Get get, Put put, ToText to_text) {
  return {{name + "_1", name + "_2", name + "_3"},
          [get, to_text](const Estimate& e, std::vector<std::string>& v) {
            for (const auto& x : get(e)) v.push_back(to_text(x));
          },
          [get, put](const Estimate& e, Idl& out) { put(out, get(e)); }};
}

template <class Estimate, class Idl, class Get, class Put>
EstimateField<Estimate, Idl> per_blade_numbers(const std::string& name, Get get, Put put) {
  return per_blade_field<Estimate, Idl>(name, get, put, [](double x) { return format_number(x); });
}

}  // namespace windfdi
