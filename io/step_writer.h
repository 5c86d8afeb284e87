#pragma once
// ISO 10303-21 ("STEP physical file") text: the exchange structure IFC files use. A StepWriter
// numbers entity instances #1, #2, ... in the order they are added and writes the HEADER and
// DATA sections; the helpers below format the parameter values (strings escaped per
// ISO 10303-21 §6.4.3, reals that read back as the same double, enumerations, references,
// lists). IfcGlobalId makes the 22-character IFC GlobalId (128 bits in IFC's base-64 alphabet)
// from a key, so the same run content gives the same ids and the same bytes.
// No schema knowledge here: the caller spells entity names (upper case) and argument lists.
// Deterministic; not thread-safe (one writer per file).

#include <string>
#include <string_view>
#include <vector>

namespace mopad::io {

/// The HEADER section's fields (ISO 10303-21 §8). No wall-clock time: `timestamp` is given.
struct StepHeader {
  std::string description = "ViewDefinition [ReferenceView]";  ///< FILE_DESCRIPTION
  std::string file_name;                                       ///< FILE_NAME name
  std::string timestamp = "1970-01-01T00:00:00";               ///< ISO 8601
  std::string author;
  std::string organization;
  std::string preprocessor = "OpenMoPAD io::StepWriter";
  std::string originating_system = "OpenMoPAD";
  std::string schema = "IFC4";  ///< FILE_SCHEMA
};

class StepWriter {
 public:
  /// Appends `TYPE(args);` as the next instance and returns its number (1, 2, ...). `type` must
  /// be an upper-case STEP keyword ([A-Z][A-Z0-9_]*); std::invalid_argument otherwise.
  int Add(std::string_view type, std::string_view args);
  /// Instances added so far.
  int Count() const { return static_cast<int>(lines_.size()); }
  /// The whole file: ISO-10303-21; HEADER; ... ENDSEC; DATA; #1=...; ENDSEC; END-ISO-10303-21;
  /// one instance per line, '\n' line ends.
  std::string Text(const StepHeader& header) const;

 private:
  std::vector<std::string> lines_;
};

/// A STEP string literal: quoted, `'` doubled, `\` doubled, printable ASCII as is, every other
/// character (UTF-8 input) as \X2\hhhh...\X0\ (UTF-16 code units, upper-case hex). Malformed
/// UTF-8 bytes become U+FFFD.
std::string StepString(std::string_view utf8);
/// A STEP real: the shortest decimal that reads back as `v`, always with a '.' and an upper-case
/// exponent ("1.", "-0.25", "1.5E-07", "1.E22"); -0 is written "0.". std::invalid_argument for NaN
/// or infinity (STEP has no such values).
std::string StepReal(double v);
/// "#n".
std::string StepRef(int id);
/// ".NAME." (upper-case enumeration value).
std::string StepEnum(std::string_view name);
/// "(a,b,c)"; "()" when empty.
std::string StepList(const std::vector<std::string>& items);
/// "(#a,#b)".
std::string StepRefList(const std::vector<int>& ids);

/// The IFC GlobalId of `key`: 128 bits from two independent 64-bit hashes of the key, written
/// as 22 characters of IFC's base-64 alphabet (0-9A-Za-z_$), the first carrying the top 2 bits.
std::string IfcGlobalId(std::string_view key);

}  // namespace mopad::io
