// The profiling hooks are compiled only into a developer build
// (-DWHITTED_DEVELOPER=ON, tools/profile_shader.sh): in any other build no
// environment can replace the tracer's shader.
#include "test_support.h"

#include <cstdlib>
#include <fstream>
#include <optional>
#include <stdexcept>
#include <string>

namespace whitted::test {
namespace {

// Sets an environment variable while it lives; puts the old value back.
class ScopedEnvironment {
public:
    ScopedEnvironment(const char* name, const std::string& value) : name_(name) {
        if (const char* old = std::getenv(name)) old_ = old;
        ::setenv(name, value.c_str(), 1);
    }
    ~ScopedEnvironment() { old_ ? ::setenv(name_, old_->c_str(), 1) : ::unsetenv(name_); }
    ScopedEnvironment(const ScopedEnvironment&) = delete;
    ScopedEnvironment& operator=(const ScopedEnvironment&) = delete;

private:
    const char* name_;
    std::optional<std::string> old_;
};

// WHITTED_SHADER_SPV naming a file that is no SPIR-V: the developer build
// refuses it, any other build never reads it and renders with its own shader.
TEST(RendererDeveloperBuild, ShaderOverrideOnlyInDeveloperBuild) {
    std::filesystem::path notSpirv = outputDir() / "developer_build_not_spirv.spv";
    std::ofstream(notSpirv, std::ios::binary) << "abc";
    ScopedEnvironment override("WHITTED_SHADER_SPV", notSpirv.string());
    const std::string xml = R"(<scene><camera><position x="0" y="0" z="0"/><window_position x="0" y="0" z="-1"/>)"
                            R"(<width>8</width><height>8</height></camera><lights></lights><objects>)"
                            R"(<object><position x="0" y="0" z="-3"/><diffuse_color r="1" g="1" b="1"/>)"
                            R"(<properties><type>sphere</type><radius>1</radius></properties></object>)"
                            R"(</objects></scene>)";
    RenderSettings settings{.samplesPerPixel = 1, .auxiliary = false};
#ifdef WHITTED_DEVELOPER
    try {
        renderXml(xml, settings);
        ADD_FAILURE() << "a developer build used a WHITTED_SHADER_SPV that is no SPIR-V";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find("WHITTED_SHADER_SPV is not a SPIR-V file"), std::string::npos) << e.what();
    }
#else
    RenderResult r = renderXml(xml, settings);
    EXPECT_EQ(r.rays.primary, 64u);
    EXPECT_EQ(r.lostSamples, 0u);
#endif
}

}  // namespace
}  // namespace whitted::test
