#pragma once

#include <stdexcept>
#include <string>

namespace sg {

/// Base of every error the toolkit throws. Messages are one line, name the thing at fault
/// (file, field, index) and say what was expected.
class Error : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

/// A BuildConfig (or another parameter set) holds a value outside its documented range.
class ConfigError : public Error {
public:
    using Error::Error;
};

/// Input geometry or rays the library cannot use: empty mesh, index out of range, NaN vertex.
class InputError : public Error {
public:
    using Error::Error;
};

/// A file whose bytes do not follow its format: bad magic, truncation, checksum mismatch,
/// out-of-range index. The message names the path and, where known, the byte offset.
class FormatError : public Error {
public:
    using Error::Error;
};

/// The operating system refused a file operation (open, read, write, rename).
class IoError : public Error {
public:
    using Error::Error;
};

}  // namespace sg

/// Debug-only check for hot paths (traversal). Compiles out when NDEBUG is defined.
#ifdef NDEBUG
#define SG_ASSERT(cond) ((void)0)
#else
#include <cassert>
#define SG_ASSERT(cond) assert(cond)
#endif
