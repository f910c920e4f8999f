// Two error channels (STYLE.md 8): user input errors carry the file, line or field and what was
// expected and end the program with exit code 2; programming mistakes are assertions (exit 1).
#pragma once
#include <stdexcept>
#include <string>

namespace shadowlab {

// Bad user input: a scene, glTF, lesson, flag or parameter. what() is the whole message, already
// naming the place ("scenes/x.json: objects[2].albedo: expected 3 numbers in [0,1], got ...").
class InputError : public std::runtime_error {
public:
    explicit InputError(const std::string& message) : std::runtime_error(message) {}
};

// Internal failure that is not the user's fault (GL context cannot be created, shader fails to
// compile): exit code 1.
class InternalError : public std::runtime_error {
public:
    explicit InternalError(const std::string& message) : std::runtime_error(message) {}
};

}  // namespace shadowlab
