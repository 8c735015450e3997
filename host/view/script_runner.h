// Carries out a loaded view script (view/view_script.h) in the live window,
// a command or more per frame: waiting commands hold it until their
// condition holds, the others act once and leave the rest of the frame to
// show their effect before the next command looks.
#pragma once

#include <chrono>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <glm/vec2.hpp>

#include "view/editor_panel.h"
#include "view/view_script.h"
#include "view/window.h"

namespace whitted {

// What a script drives: the window's input (as InputSink) and what its keys
// and panel do. view/view_app.cpp implements it.
class ScriptTarget : public InputSink {
public:
    virtual long framesDrawn() const = 0;
    virtual uint32_t completedSamples() const = 0;  // every pixel has at least this many
    virtual long reloads() const = 0;               // scene file changes seen, loaded or refused
    virtual glm::dvec2 cursor() const = 0;
    // What the editor panel does; an error text when it cannot.
    virtual std::optional<std::string> editObject(int object, ObjectField field, double value) = 0;
    virtual void select(bool light, int index) = 0;
    virtual void showLayer(size_t index) = 0;  // into layerViews
    // Shows the ray tree of image pixel (x, y); an error text when it is outside the image.
    virtual std::optional<std::string> pickPixel(int x, int y) = 0;
    virtual void screenshotAfterFrame(const std::filesystem::path& path, bool window) = 0;
    virtual void saveImages() = 0;
    virtual void saveScene() = 0;
};

enum class ScriptStep {
    Running,   // carry on with the frame
    Quit,      // `quit`: finish this frame, then close
    Refused,   // a command could not be carried out (FILE:LINE printed)
    TimedOut,  // a wait ran past kScriptWaitSeconds (FILE:LINE printed)
};

class ScriptRunner {
public:
    ScriptRunner(std::filesystem::path path, std::vector<ScriptCommand> commands);

    // Runs commands until one has to wait, or one that acts has acted.
    ScriptStep step(ScriptTarget& target);
    bool finished() const { return next_ >= commands_.size(); }

private:
    using Clock = std::chrono::steady_clock;
    void advance();  // to the next command; its wait starts now

    std::filesystem::path path_;
    std::vector<ScriptCommand> commands_;
    size_t next_ = 0;
    Clock::time_point waitStart_ = Clock::now();
    long waitFrames_ = -1;            // the frame `frames` waits for
    std::optional<long> reloadMark_;  // the reload count `reload` waits to exceed
    std::optional<std::pair<int, Clock::time_point>> hold_;  // the key `hold` holds, since when
};

}  // namespace whitted
