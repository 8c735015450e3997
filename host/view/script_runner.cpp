#include "view/script_runner.h"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <fstream>
#include <iostream>
#include <iterator>

namespace whitted {

ScriptRunner::ScriptRunner(std::filesystem::path path, std::vector<ScriptCommand> commands)
    : path_(std::move(path)), commands_(std::move(commands)) {}

ScriptStep ScriptRunner::step(ScriptTarget& target) {
    while (next_ < commands_.size()) {
        const ScriptCommand& c = commands_[next_];
        const ScriptAction& a = c.action;
        auto fail = [&](const std::string& what) {
            std::cerr << path_.string() << ":" << c.line << ": " << what << "\n";
            return ScriptStep::Refused;
        };
        double elapsed = std::chrono::duration<double>(Clock::now() - waitStart_).count();
        if (elapsed > kScriptWaitSeconds) {
            std::cerr << path_.string() << ":" << c.line << ": '" << c.name << "' still waiting after "
                      << kScriptWaitSeconds << " s\n";
            return ScriptStep::TimedOut;
        }

        // Waiting commands.
        if (const auto* frames = std::get_if<script::Frames>(&a)) {
            if (waitFrames_ < 0) waitFrames_ = target.framesDrawn() + frames->count;
            if (target.framesDrawn() < waitFrames_) return ScriptStep::Running;
            waitFrames_ = -1;
        } else if (const auto* spp = std::get_if<script::Spp>(&a)) {
            if (target.completedSamples() < spp->samples) return ScriptStep::Running;
        } else if (std::holds_alternative<script::Reload>(a)) {
            // A reload after the last file edit of the script (it may have
            // happened already, in the frame of the edit).
            if (!reloadMark_) reloadMark_ = target.reloads();
            if (target.reloads() <= *reloadMark_) return ScriptStep::Running;
            reloadMark_.reset();
        } else if (const auto* hold = std::get_if<script::Hold>(&a)) {
            if (!hold_) {
                hold_ = {hold->key, Clock::now()};
                target.onKey(hold->key, GLFW_PRESS, 0);
            }
            if (std::chrono::duration<double>(Clock::now() - hold_->second).count() < hold->seconds)
                return ScriptStep::Running;
            target.onKey(hold->key, GLFW_RELEASE, 0);
            hold_.reset();

            // Immediate commands.
        } else if (const auto* key = std::get_if<script::Key>(&a)) {
            target.onKey(key->key, GLFW_PRESS, 0);
            target.onKey(key->key, GLFW_RELEASE, 0);
        } else if (const auto* drag = std::get_if<script::Drag>(&a)) {
            glm::dvec2 start = target.cursor();
            target.onMouseButton(drag->button, GLFW_PRESS, start.x, start.y);
            target.onCursor(start.x + drag->dx, start.y + drag->dy);
            target.onMouseButton(drag->button, GLFW_RELEASE, start.x + drag->dx, start.y + drag->dy);
        } else if (const auto* scroll = std::get_if<script::Scroll>(&a)) {
            target.onScroll(scroll->steps);
        } else if (const auto* copy = std::get_if<script::Copy>(&a)) {
            std::error_code ec;
            std::filesystem::copy_file(copy->from, copy->to, std::filesystem::copy_options::overwrite_existing, ec);
            if (ec) return fail("copy: " + ec.message());
            reloadMark_ = target.reloads();
        } else if (const auto* replace = std::get_if<script::Replace>(&a)) {
            std::ifstream in(replace->file, std::ios::binary);
            std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
            size_t at = text.find(replace->text);
            if (!in || at == std::string::npos)
                return fail("replace: '" + replace->text + "' not found in " + replace->file.string());
            text.replace(at, replace->text.size(), replace->replacement);
            std::ofstream(replace->file, std::ios::binary | std::ios::trunc) << text;  // in place, as an editor would
            reloadMark_ = target.reloads();
        } else if (const auto* edit = std::get_if<script::Edit>(&a)) {
            if (auto error = target.editObject(edit->object, edit->field, edit->value)) return fail("edit: " + *error);
        } else if (const auto* select = std::get_if<script::Select>(&a)) {
            target.select(select->light, select->index);
        } else if (const auto* pick = std::get_if<script::Pick>(&a)) {
            if (auto error = target.pickPixel(pick->x, pick->y)) return fail("pick: " + *error);
        } else if (const auto* layer = std::get_if<script::Layer>(&a)) {
            target.showLayer(layer->index);
        } else if (const auto* shot = std::get_if<script::Screenshot>(&a)) {
            // Taken after this frame is drawn; later commands wait for it.
            target.screenshotAfterFrame(shot->path, shot->window);
            advance();
            return ScriptStep::Running;
        } else if (std::holds_alternative<script::SaveImages>(a)) {
            target.saveImages();
        } else if (std::holds_alternative<script::SaveScene>(a)) {
            target.saveScene();
        } else if (std::holds_alternative<script::Quit>(a)) {
            ++next_;
            return ScriptStep::Quit;
        }
        // One command per frame: what it changed (a restart, a reload) is
        // in place before the next command looks at the state. A wait that
        // is over lets the next command run in the same frame.
        bool waited = std::holds_alternative<script::Frames>(a) || std::holds_alternative<script::Spp>(a) ||
                      std::holds_alternative<script::Reload>(a) || std::holds_alternative<script::Hold>(a);
        advance();
        if (!waited) return ScriptStep::Running;
    }
    return ScriptStep::Running;
}

void ScriptRunner::advance() {
    ++next_;
    waitStart_ = Clock::now();
}

}  // namespace whitted
