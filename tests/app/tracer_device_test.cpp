// The references' device: `auto` picks the device that traced more paths per second here
// (app/pipeline/tracer_device.h), not a vendor string; the choice is shown, connections stay
// on the CPU, a GL tracer that cannot build leaves the CPU in charge, and captures written
// before the setting existed ("gpu": true/false, or neither: the CPU then) still load.
#include "../support/gl_fixture.h"
#include "captures/capture_io.h"
#include "captures/settings_json.h"
#include "pipeline/tracer_device.h"
#include "pipeline/workbench.h"

#include <string>

namespace {

std::string statOf(const app::StageStatus& st, const std::string& name) {
    for (const auto& [k, v] : st.stats)
        if (k == name) return v;
    return "";
}

} // namespace

TEST(TracerDevice, AutoTakesTheDeviceThatMeasuredFaster) {
    testsupport::context();
    auto root = testsupport::makeProjectRoot("device", {"dipole.bssrdf"});
    const auto shader = root / "shaders/pathtrace_slab.comp";
    const app::ThroughputProbe& probe = app::slabThroughput(shader);
    EXPECT_TRUE(probe.gpuProblem.empty()) << probe.gpuProblem;
    EXPECT_GT(probe.cpuPathsPerSecond, 1e3);
    EXPECT_GT(probe.gpuPathsPerSecond, 1e3);
    EXPECT_EQ(&app::slabThroughput(shader), &probe); // measured once per process
    std::printf("%s\n", probe.summary().c_str());
    EXPECT_EQ(app::chooseGpu(app::TracerDevice::Auto, shader), probe.gpuFaster());
    EXPECT_FALSE(app::chooseGpu(app::TracerDevice::Cpu, shader));
    EXPECT_TRUE(app::chooseGpu(app::TracerDevice::Gpu, shader));

    app::Workbench wb(root, false);
    wb.applyPreset(wb.shared(), "Skin1");
    auto& rs = wb.referenceSettings();
    EXPECT_EQ(rs.device, app::TracerDevice::Auto); // the default, in the GUI, CLI and captures
    rs.enabled = true;
    rs.paths = 4000;
    rs.bins = 10;
    wb.update();
    app::ReferenceSnapshot snap = wb.finishReference();
    ASSERT_TRUE(snap.problem.empty()) << snap.problem;
    EXPECT_EQ(snap.device, probe.gpuFaster() ? "GPU" : "CPU");
    EXPECT_EQ(statOf(wb.reference().status(), "device choice"), probe.summary());

    // the slice takes the same measured choice and shows it
    wb.sliceSettings().enabled = true;
    wb.sliceSettings().paths = 20000;
    wb.update();
    EXPECT_EQ(wb.slice().deviceChoice(), probe.summary());
    EXPECT_EQ(statOf(wb.slice().status(), "device choice"), probe.summary());
    EXPECT_EQ(wb.slice().snapshot().device, probe.gpuFaster() ? "GPU" : "CPU");
    // a capture writes the devices that ran, not `auto`
    const capture::Manifest m = app::captureInputs(wb, "devices", -1, -1);
    EXPECT_EQ(m.settings["reference"]["device"], "auto");
    app::CaptureEntries ran;
    wb.capture(ran);
    const std::string traced = probe.gpuFaster() ? "gpu" : "cpu";
    ASSERT_EQ(ran.resolved.size(), 2u);
    EXPECT_EQ(ran.resolved[0].section + "." + ran.resolved[0].key + "=" + ran.resolved[0].value,
              "reference.device=" + traced);
    EXPECT_EQ(ran.resolved[1].section + "." + ran.resolved[1].key + "=" + ran.resolved[1].value,
              "slice.device=" + traced);
    wb.sliceSettings().enabled = false;
    wb.update();

    // connections have no GL tracer: auto keeps them on the CPU and says why
    rs.estimator = pathtrace::Estimator::Connections;
    wb.update();
    snap = wb.finishReference();
    ASSERT_TRUE(snap.problem.empty()) << snap.problem;
    EXPECT_EQ(snap.device, "CPU");
    EXPECT_NE(statOf(wb.reference().status(), "device choice").find("connections"),
              std::string::npos);
    std::filesystem::remove_all(root);
}

TEST(TracerDevice, AGlTracerThatDoesNotBuildLeavesTheCpu) {
    testsupport::context();
    auto root = testsupport::makeProjectRoot("device_bad", {"dipole.bssrdf"});
    const auto shader = root / "shaders/pathtrace_slab.comp";
    core::writeFile(shader, "#version 450\nlayout(local_size_x = 64) in;\nvoid main() { oops; }\n");
    const app::ThroughputProbe probe = app::measureSlabThroughput(shader, {}, 5.0);
    EXPECT_NE(probe.gpuProblem.find("pathtrace_slab.comp:3"), std::string::npos)
        << probe.gpuProblem;
    EXPECT_FALSE(probe.gpuFaster());
    EXPECT_GT(probe.cpuPathsPerSecond, 1e3);
    EXPECT_NE(probe.summary().find("pathtrace_slab.comp:3"), std::string::npos);
    std::filesystem::remove_all(root);
}

TEST(TracerDevice, CapturesWrittenWithTheGpuSwitchStillLoad) {
    testsupport::context();
    auto root = testsupport::makeProjectRoot("device_json", {"dipole.bssrdf"});
    app::Workbench wb(root, false);
    int x = 0, y = 0;
    app::applySettingsJson(wb, nlohmann::json::parse(R"({"reference": {"gpu": true}})"), "m.json",
                           x, y);
    EXPECT_EQ(wb.referenceSettings().device, app::TracerDevice::Gpu);
    app::applySettingsJson(wb, nlohmann::json::parse(R"({"reference": {"gpu": false}})"), "m.json",
                           x, y);
    EXPECT_EQ(wb.referenceSettings().device, app::TracerDevice::Cpu);
    app::applySettingsJson(wb, nlohmann::json::parse(R"({"reference": {"device": "auto"}})"),
                           "m.json", x, y);
    EXPECT_EQ(wb.referenceSettings().device, app::TracerDevice::Auto);
    // without either key the capture predates the GL tracers: the CPU walk recorded it
    app::applySettingsJson(wb, nlohmann::json::parse(R"({"reference": {"paths": 100}})"), "m.json",
                           x, y);
    EXPECT_EQ(wb.referenceSettings().device, app::TracerDevice::Cpu);
    try {
        app::applySettingsJson(wb, nlohmann::json::parse(R"({"reference": {"gpu": 3}})"), "m.json",
                               x, y);
        ADD_FAILURE() << "a non-boolean gpu was accepted";
    } catch (const core::Error& e) {
        EXPECT_NE(std::string(e.what()).find("m.json"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("settings.reference.gpu"), std::string::npos)
            << e.what();
    }
    try {
        app::applySettingsJson(wb, nlohmann::json::parse(R"({"reference": {"device": "tpu"}})"),
                               "m.json", x, y);
        ADD_FAILURE() << "an unknown device was accepted";
    } catch (const core::Error& e) {
        EXPECT_NE(std::string(e.what()).find("auto | cpu | gpu"), std::string::npos) << e.what();
    }
    std::filesystem::remove_all(root);
}
