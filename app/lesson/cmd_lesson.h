// The command line's side of lessons (app/lesson/cmd_lesson.cpp).
#pragma once
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace shadowlab {

int commandLesson(const std::vector<std::string>& args);
// Every lesson in lessons/ with its title, step and task counts (or the error that stops it loading).
nlohmann::json describeLessons();

}  // namespace shadowlab
