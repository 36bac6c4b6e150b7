// The workbench in a real window: the program (BW_EXE) started with a display, an X server of its
// own (Xvfb, which ./run installs), as a user starts it. Checked from outside, through the X
// server, as a user would see and use it: the window opens at the size asked for (or the one the
// last session saved, or shrunk to fit the screen; twice the pixels on a desktop that scales by
// 2), draws the workbench as the headless GUI does, answers the mouse and the keyboard through
// GLFW (a click opens the File menu, Ctrl+Q quits), opens a file dropped on it from a file
// manager (XDND), shows a saved model's new pixels (hot reload) and names a broken one, closes
// on SIGINT (Ctrl-C in its terminal) or SIGTERM as File > Quit does (exit 0, the layout and the
// session saved), and starts again where it closed. Label `window`; the GPU test bundle leaves
// these out (the machines it runs on have no X server).
#include "gl/gl.h"
#include "scratch_dir.h"
#include "x_display.h"

#include <X11/Xatom.h>
#include <X11/extensions/XTest.h>
#include <X11/keysym.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <fcntl.h>
#include <poll.h>
#include <sys/wait.h>
#include <unistd.h>

namespace {
namespace fs = std::filesystem;
using namespace xtest;

class GuiWindow : public ::testing::Test {
  protected:
    static constexpr const char* kTitle = "BSSRDF Workbench";

    void SetUp() override { startServer(1280, 800); }

    void startServer(int width, int height) {
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        m_dir = fs::temp_directory_path() /
                (std::string("bw_window_") + info->name() + "_" + std::to_string(::getpid()));
        m_x.reset();
        fs::remove_all(m_dir);
        m_config = m_dir / "config";
        fs::create_directories(m_config);
        testsupport::removeAtExit(m_dir);
        m_x = std::make_unique<XServer>(m_dir, width, height);
        ASSERT_EQ(m_x->problem(), "");
    }

    // The desktop's scaling, as desktops publish it to X programs: Xft.dpi in the root window's
    // resources (96 per 1), which GLFW reads as the windows' content scale.
    void setDesktopScale(int dpi) {
        Display* d = m_x->display();
        const std::string resources = "Xft.dpi:\t" + std::to_string(dpi) + "\n";
        XChangeProperty(d, DefaultRootWindow(d), XA_RESOURCE_MANAGER, XA_STRING, 8, PropModeReplace,
                        reinterpret_cast<const unsigned char*>(resources.data()),
                        int(resources.size()));
        XSync(d, False);
    }

    // The workbench on this test's display, its settings under this test's folder.
    std::unique_ptr<Process> start(std::vector<std::string> args,
                                   const std::string& root = BW_SOURCE_ROOT) {
        std::vector<std::string> argv = {BW_EXE, "-v", "--root", root};
        argv.insert(argv.end(), args.begin(), args.end());
        return std::make_unique<Process>(
            argv,
            std::vector<std::string>{"DISPLAY=" + m_x->name(), "HOME=" + m_dir.string(),
                                     "XDG_CONFIG_HOME=" + m_config.string()},
            m_dir / ("workbench" + std::to_string(m_runs++) + ".log"));
    }

    // The window once it is mapped and shows the workbench drawn (its menu bar and panels: many
    // colours where a window not yet drawn is one); 0 if not within `seconds`.
    Window drawnWindow(Process& p, double seconds = 60, const std::string& title = kTitle) {
        const auto start = Clock::now();
        while (secondsSince(start) < seconds && p.running()) {
            if (Window w = findWindow(m_x->display(), title)) {
                const Image img = grab(m_x->display(), w);
                if (img.width > 0 && distinctColours(img, 0, 0, img.width, img.height) > 40)
                    return w;
            }
            std::this_thread::sleep_for(std::chrono::milliseconds(200));
        }
        return 0;
    }

    void save(const Image& img, const std::string& name) {
        if (const char* dir = std::getenv("BW_WINDOW_PNG_DIR"))
            gl::writePng(fs::path(dir) / name, img.width, img.height, img.rgba);
    }

    std::string layoutFile() const { return readText(m_config / "bssrdf-workbench" / "imgui.ini"); }

    // Moves the pointer to (x, y) in window `w`'s coordinates.
    void pointTo(Window w, int x, int y) {
        Display* d = m_x->display();
        int rx = 0, ry = 0;
        Window child = 0;
        XTranslateCoordinates(d, w, DefaultRootWindow(d), x, y, &rx, &ry, &child);
        XTestFakeMotionEvent(d, DefaultScreen(d), rx, ry, CurrentTime);
        XFlush(d);
    }
    void click(Window w, int x, int y) {
        Display* d = m_x->display();
        pointTo(w, x, y);
        std::this_thread::sleep_for(std::chrono::milliseconds(300));
        XTestFakeButtonEvent(d, 1, True, CurrentTime);
        XFlush(d);
        std::this_thread::sleep_for(std::chrono::milliseconds(150));
        XTestFakeButtonEvent(d, 1, False, CurrentTime);
        XFlush(d);
    }
    // Presses and releases `sym` (with Control), held `holdMs`; 0: a tap whose press and release
    // reach the window together, as a quick one does while a frame takes longer than the tap.
    void key(KeySym sym, bool control = false, int holdMs = 150) {
        Display* d = m_x->display();
        const KeyCode ctrl = XKeysymToKeycode(d, XK_Control_L), k = XKeysymToKeycode(d, sym);
        if (control) XTestFakeKeyEvent(d, ctrl, True, CurrentTime);
        if (holdMs > 0) XFlush(d);
        if (holdMs > 0) std::this_thread::sleep_for(std::chrono::milliseconds(100));
        XTestFakeKeyEvent(d, k, True, CurrentTime);
        if (holdMs > 0) XFlush(d);
        std::this_thread::sleep_for(std::chrono::milliseconds(holdMs));
        XTestFakeKeyEvent(d, k, False, CurrentTime);
        if (control) XTestFakeKeyEvent(d, ctrl, False, CurrentTime);
        XFlush(d);
    }

    // Drops `file` on window `w` at (x, y) as a file manager does: the XDND protocol (version
    // 5) from a window of this test's own: enter with text/uri-list, position, drop; the target
    // asks for the selection, which this answers with the file's URI, until it says finished.
    // False when the target never accepted or never finished within 20 s.
    bool dropFile(Window w, const fs::path& file, int x, int y) {
        Display* d = m_x->display();
        const auto atom = [d](const char* name) { return XInternAtom(d, name, False); };
        const Atom enter = atom("XdndEnter"), position = atom("XdndPosition"),
                   status = atom("XdndStatus"), drop = atom("XdndDrop"),
                   finished = atom("XdndFinished"), selection = atom("XdndSelection"),
                   uriList = atom("text/uri-list"), copy = atom("XdndActionCopy");
        const Window source = XCreateSimpleWindow(d, DefaultRootWindow(d), 0, 0, 1, 1, 0, 0, 0);
        XSetSelectionOwner(d, selection, source, CurrentTime);
        const auto send = [&](Atom type, long l1, long l2, long l3, long l4) {
            XEvent e{};
            e.xclient.type = ClientMessage;
            e.xclient.display = d;
            e.xclient.window = w;
            e.xclient.message_type = type;
            e.xclient.format = 32;
            e.xclient.data.l[0] = long(source);
            e.xclient.data.l[1] = l1;
            e.xclient.data.l[2] = l2;
            e.xclient.data.l[3] = l3;
            e.xclient.data.l[4] = l4;
            XSendEvent(d, w, False, NoEventMask, &e);
            XFlush(d);
        };
        int rx = 0, ry = 0;
        Window child = 0;
        XTranslateCoordinates(d, w, DefaultRootWindow(d), x, y, &rx, &ry, &child);
        send(enter, 5L << 24, long(uriList), None, None);
        send(position, 0, (long(rx) << 16) | ry, CurrentTime, long(copy));
        bool accepted = false, dropped = false, done = false;
        const std::string uri = "file://" + file.string() + "\r\n";
        const auto since = Clock::now();
        while (!done && secondsSince(since) < 20) {
            if (!XPending(d)) {
                std::this_thread::sleep_for(std::chrono::milliseconds(20));
                continue;
            }
            XEvent e{};
            XNextEvent(d, &e);
            if (e.type == ClientMessage && e.xclient.message_type == status) {
                accepted = (e.xclient.data.l[1] & 1) != 0;
                if (accepted && !dropped) {
                    send(drop, 0, CurrentTime, 0, 0);
                    dropped = true;
                }
            } else if (e.type == SelectionRequest) {
                const XSelectionRequestEvent& r = e.xselectionrequest;
                XChangeProperty(d, r.requestor, r.property, r.target, 8, PropModeReplace,
                                reinterpret_cast<const unsigned char*>(uri.data()),
                                int(uri.size()));
                XEvent n{};
                n.xselection.type = SelectionNotify;
                n.xselection.requestor = r.requestor;
                n.xselection.selection = r.selection;
                n.xselection.target = r.target;
                n.xselection.property = r.property;
                n.xselection.time = r.time;
                XSendEvent(d, r.requestor, False, NoEventMask, &n);
                XFlush(d);
            } else if (e.type == ClientMessage && e.xclient.message_type == finished) {
                done = true;
            }
        }
        XDestroyWindow(d, source);
        XFlush(d);
        return accepted && done;
    }

    std::pair<int, int> windowSize(Window w) {
        XWindowAttributes a{};
        XGetWindowAttributes(m_x->display(), w, &a);
        return {a.width, a.height};
    }

    // The same workbench as the headless GUI draws (gui.h: same panels, same pixels) at UI
    // `scale`: the menu bar's menus and the panels' tab bars below it (the top 45 units), pixel
    // for pixel, once the layout has settled (the menu bar's right end shows the run's own
    // state: hot reload on, not off). Saves what the window showed as `png`.
    void expectDrawnAsHeadless(Window w, int scale, const std::string& png) {
        auto shot = start({"screenshot", "--size", "900x600", "--ui-scale", std::to_string(scale),
                           "--out", (m_dir / "headless.png").string()});
        ASSERT_EQ(shot->wait(120), 0) << shot->output();
        const Image headless = readPng(m_dir / "headless.png");
        ASSERT_EQ(headless.width, 900 * scale);
        const auto bars = [&](const Image& img) {
            return pixelsThatDiffer(img, headless, 0, 0, 200 * scale, 20 * scale) +
                   pixelsThatDiffer(img, headless, 0, 20 * scale, 900 * scale, 45 * scale);
        };
        Image img;
        const auto since = Clock::now();
        do {
            img = grab(m_x->display(), w);
        } while (bars(img) > 0 && secondsSince(since) < 20);
        save(img, png);
        EXPECT_EQ(bars(img), 0u) << "the menu bar's menus and the panels' tab bars";
        EXPECT_GT(distinctColours(img, 0, 45 * scale, img.width, img.height), 40u)
            << "the panels' contents";
    }

    // A click on "File" (18, 9 UI units: the menu bar's first item) opens its menu: most of a
    // 100x60-unit block below it changes. Escape closes it again.
    void expectClickOpensTheFileMenu(Window w, int scale, const std::string& png) {
        Display* d = m_x->display();
        XSetInputFocus(d, w, RevertToParent, CurrentTime); // a window manager's part, here none
        pointTo(w, 600 * scale, 300 * scale);
        std::this_thread::sleep_for(std::chrono::milliseconds(500));
        const Image before = grab(d, w);
        click(w, 18 * scale, 9 * scale);
        const auto changed = [&](const Image& open) {
            return pixelsThatDiffer(before, open, 4 * scale, 24 * scale, 104 * scale, 84 * scale);
        };
        const size_t most = size_t(3000 * scale * scale);
        Image open;
        const auto since = Clock::now();
        do {
            std::this_thread::sleep_for(std::chrono::milliseconds(200));
            open = grab(d, w);
        } while (changed(open) < most && secondsSince(since) < 20);
        save(open, png);
        EXPECT_GE(changed(open), most) << "the File menu did not open";
        key(XK_Escape);
    }

    fs::path m_dir, m_config; // the test's folder; the programs' configuration folder
    std::unique_ptr<XServer> m_x;
    int m_runs = 0;
};

// Asked for 900x600: that window, drawn; SIGINT (Ctrl-C where it was started) closes it as Quit
// does, the layout saved with its size; started again without --size it opens at that size.
TEST_F(GuiWindow, OpensAtItsSizeDrawsAndCtrlCClosesItKeepingTheLayout) {
    auto p = start({"gui", "--size", "900x600"});
    const Window w = drawnWindow(*p);
    ASSERT_NE(w, 0u) << "no drawn window within 60 s:\n" << p->output();
    EXPECT_EQ(windowSize(w), std::make_pair(900, 600));
    expectDrawnAsHeadless(w, 1, "window_900x600.png");
    ASSERT_TRUE(p->waitForOutput("checking its first evaluation", 30)) << p->output();
    ::kill(p->pid(), SIGINT);
    const int rc = p->wait(20);
    EXPECT_EQ(rc, 0) << p->output();
    EXPECT_NE(p->output().find("closed the window on SIGINT"), std::string::npos) << p->output();
    const std::string layout = layoutFile();
    EXPECT_NE(layout.find("[BssrdfWorkbench][Panels]"), std::string::npos) << layout;
    EXPECT_NE(layout.find("Window=900,600"), std::string::npos) << layout;

    auto again = start({"gui"});
    const Window w2 = drawnWindow(*again);
    ASSERT_NE(w2, 0u) << again->output();
    EXPECT_EQ(windowSize(w2), std::make_pair(900, 600)) << "the size the last session saved";
    ::kill(again->pid(), SIGTERM);
    EXPECT_EQ(again->wait(20), 0) << again->output();
    EXPECT_NE(again->output().find("closed the window on SIGTERM"), std::string::npos);
}

// On a desktop that scales by 2 (a 4K screen at 200 %): the window is twice the size asked for
// in pixels, its menu bar and tab bars are the headless GUI's at --ui-scale 2 pixel for pixel,
// a click where "File" shows opens it (the mouse in UI units), and the layout keeps the size in
// UI units, as asked for.
TEST_F(GuiWindow, OnADesktopScaledBy2TheWindowIsTwiceAsLargeAndAnswersTheMouse) {
    startServer(2560, 1600);
    setDesktopScale(192);
    auto p = start({"gui", "--size", "900x600"});
    const Window w = drawnWindow(*p);
    ASSERT_NE(w, 0u) << p->output();
    EXPECT_EQ(windowSize(w), std::make_pair(1800, 1200));
    expectDrawnAsHeadless(w, 2, "window_scale2.png");
    expectClickOpensTheFileMenu(w, 2, "window_scale2_file_menu.png");
    key(XK_q, true);
    EXPECT_EQ(p->wait(20), 0) << p->output();
    EXPECT_NE(layoutFile().find("Window=900,600"), std::string::npos) << layoutFile();
}

// With no size asked for and none saved, the default (1600x1000) shrunk to fit a 1280x800 screen.
TEST_F(GuiWindow, TheDefaultSizeIsShrunkToFitTheScreen) {
    auto p = start({"gui"});
    const Window w = drawnWindow(*p);
    ASSERT_NE(w, 0u) << p->output();
    const auto [width, height] = windowSize(w);
    EXPECT_LE(width, 1280);
    EXPECT_LE(height, 800);
    EXPECT_NEAR(double(width) / height, 1.6, 0.01) << width << "x" << height;
    ::kill(p->pid(), SIGTERM);
    EXPECT_EQ(p->wait(20), 0) << p->output();
}

// The mouse and the keyboard through GLFW: a click on "File" opens its menu (new pixels below
// it), Escape closes it, Ctrl+Q quits with exit 0 and the layout saved.
TEST_F(GuiWindow, AClickOpensTheFileMenuAndCtrlQQuits) {
    auto p = start({"gui", "--size", "900x600"});
    const Window w = drawnWindow(*p);
    ASSERT_NE(w, 0u) << p->output();
    expectClickOpensTheFileMenu(w, 1, "window_file_menu.png");
    key(XK_q, true);
    EXPECT_EQ(p->wait(20), 0) << "Ctrl+Q did not quit:\n" << p->output();
    EXPECT_NE(layoutFile().find("Window=900,600"), std::string::npos) << layoutFile();
}

// A shortcut typed quickly, its press and release both between two frames (a frame takes
// 150 ms and more on llvmpipe while the scene renders; a tap is shorter): ImGui 1.86's GLFW
// backend sets a key's state to its last event, so such a tap was never seen down
// (gui/key_taps.h). Ctrl+Q tapped so quits.
TEST_F(GuiWindow, AShortcutTappedWithinOneFrameIsSeen) {
    auto p = start({"gui", "--size", "900x600"});
    const Window w = drawnWindow(*p);
    ASSERT_NE(w, 0u) << p->output();
    XSetInputFocus(m_x->display(), w, RevertToParent, CurrentTime);
    std::this_thread::sleep_for(std::chrono::milliseconds(500));
    key(XK_q, true, 0);
    EXPECT_EQ(p->wait(20), 0) << "a tapped Ctrl+Q did not quit:\n" << p->output();
}

// A save to a model the window shows: new pixels (the program's own measure, "save to new
// pixels", taken after the window's buffer swap); a broken save is named with its file and line
// and the window stays; the repair is shown again.
TEST_F(GuiWindow, ASavedModelIsShownAndABrokenOneNamedWhileTheWindowStays) {
    const fs::path root = m_dir / "project";
    for (const char* dir : {"shaders", "third_party/bunny", "materials/env"})
        fs::create_directories(root / dir);
    fs::copy(fs::path(BW_SOURCE_ROOT) / "shaders", root / "shaders", fs::copy_options::recursive);
    fs::copy(fs::path(BW_SOURCE_ROOT) / "materials/env", root / "materials/env",
             fs::copy_options::recursive);
    for (const char* f :
         {"materials/presets.json", "materials/dipole.bssrdf", "third_party/bunny/bunny.obj"})
        fs::copy_file(fs::path(BW_SOURCE_ROOT) / f, root / f);
    const fs::path model = root / "materials/dipole.bssrdf";
    const std::string good = readText(model);

    auto p = start({"gui", "--size", "900x600"}, root.string());
    const Window w = drawnWindow(*p);
    ASSERT_NE(w, 0u) << p->output();
    ASSERT_TRUE(p->waitForOutput("checking its first evaluation", 30)) << p->output();
    std::this_thread::sleep_for(std::chrono::seconds(2));

    size_t mark = p->output().size();
    std::ofstream(model, std::ios::binary) << good << "\nthis is not a section\n";
    const std::string line = std::to_string(std::count(good.begin(), good.end(), '\n') + 2);
    EXPECT_TRUE(p->waitForOutput("keeping the last good version: materials/dipole.bssrdf:" + line +
                                     ": unexpected text outside a section",
                                 30, mark))
        << p->output();
    EXPECT_TRUE(p->running()) << p->output();
    EXPECT_NE(findWindow(m_x->display(), kTitle), 0u);

    mark = p->output().size();
    std::ofstream(model, std::ios::binary) << good;
    EXPECT_TRUE(p->waitForOutput("hot reload: save to new pixels", 30, mark)) << p->output();
    EXPECT_EQ(p->output().find("keeping the last good version", mark), std::string::npos)
        << p->output();
    save(grab(m_x->display(), w), "window_reloaded.png");

    ::kill(p->pid(), SIGINT);
    EXPECT_EQ(p->wait(20), 0) << p->output();
}

// The window keeps its state for the next start on the project (captures/session.h): a model
// opened from elsewhere (here on the command line, as `gui FILE`) is opened again where it is;
// `gui --fresh` starts without it; a model file that is not there, or not a model, is refused
// before the window opens.
TEST_F(GuiWindow, TheNextStartHasTheLastSessionAndFreshStartsWithout) {
    const fs::path model = m_dir / "mine.bssrdf";
    fs::copy_file(fs::path(BW_SOURCE_ROOT) / "materials/better_dipole.bssrdf", model);
    const std::string opened = "[info] opened " + model.string();
    auto p = start({"gui", "--size", "900x600", model.string()});
    ASSERT_NE(drawnWindow(*p), 0u) << p->output();
    ASSERT_TRUE(p->waitForOutput(opened, 30)) << p->output();
    EXPECT_EQ(p->output().find("restored the last session"), std::string::npos) << p->output();
    ::kill(p->pid(), SIGINT);
    ASSERT_EQ(p->wait(20), 0) << p->output();
    EXPECT_TRUE(fs::exists(m_config / "bssrdf-workbench" / "sessions"));

    auto again = start({"gui", "--size", "900x600"});
    ASSERT_NE(drawnWindow(*again), 0u) << again->output();
    EXPECT_TRUE(again->waitForOutput(opened, 30)) << again->output();
    EXPECT_NE(again->output().find("restored the last session of"), std::string::npos)
        << again->output();
    ::kill(again->pid(), SIGTERM);
    ASSERT_EQ(again->wait(20), 0) << again->output();

    auto fresh = start({"gui", "--size", "900x600", "--fresh"});
    ASSERT_NE(drawnWindow(*fresh), 0u) << fresh->output();
    ASSERT_TRUE(fresh->waitForOutput("dipole.bssrdf: checking its first evaluation", 30))
        << fresh->output();
    EXPECT_EQ(fresh->output().find("mine.bssrdf"), std::string::npos) << fresh->output();
    EXPECT_EQ(fresh->output().find("restored"), std::string::npos) << fresh->output();
    ::kill(fresh->pid(), SIGTERM);
    ASSERT_EQ(fresh->wait(20), 0) << fresh->output();

    auto missing = start({"gui", (m_dir / "gone.bssrdf").string()});
    const int rc = missing->wait(30);
    EXPECT_TRUE(rc > 0 && rc < 128) << rc << "\n" << missing->output();
    EXPECT_NE(missing->output().find("gone.bssrdf"), std::string::npos) << missing->output();
    EXPECT_EQ(findWindow(m_x->display(), kTitle), 0u);
    fs::copy_file(model, m_dir / "mine.bssrdf.txt");
    auto notAModel = start({"gui", (m_dir / "mine.bssrdf.txt").string()});
    const int rc2 = notAModel->wait(30);
    EXPECT_TRUE(rc2 > 0 && rc2 < 128) << rc2 << "\n" << notAModel->output();
    EXPECT_NE(notAModel->output().find("not a .bssrdf model file"), std::string::npos)
        << notAModel->output();
}

// A window on a capture (`gui --capture NAME`, as the Captures panel's "Open in a window"
// starts it): its title names the capture, it shows the recorded state, and closing it leaves
// the project's session and layout as they were (neither is written).
TEST_F(GuiWindow, AWindowOnACaptureNamesItAndLeavesTheSessionAsItWas) {
    auto p = start({"gui", "--size", "900x600", "--capture", "dipole_marble"});
    const Window w = drawnWindow(*p, 60, std::string(kTitle) + " - capture dipole_marble");
    ASSERT_NE(w, 0u) << "no drawn window within 60 s:\n" << p->output();
    EXPECT_EQ(windowSize(w), std::make_pair(900, 600));
    EXPECT_TRUE(p->waitForOutput("opened capture dipole_marble", 30)) << p->output();
    save(grab(m_x->display(), w), "window_capture.png");
    ::kill(p->pid(), SIGTERM);
    EXPECT_EQ(p->wait(20), 0) << p->output();
    EXPECT_NE(p->output().find("the project's session and layout are as they were"),
              std::string::npos)
        << p->output();
    EXPECT_FALSE(fs::exists(m_config / "bssrdf-workbench" / "imgui.ini"));
    EXPECT_FALSE(fs::exists(m_config / "bssrdf-workbench" / "sessions"));
}

// Files dropped on the window from a file manager (XDND) open as what they are (gui/
// file_drop.h): a model from elsewhere is opened; a file the workbench does not open is an
// error naming it, and the window stays.
TEST_F(GuiWindow, AFileDroppedOnTheWindowOpens) {
    const fs::path model = m_dir / "dropped.bssrdf", text = m_dir / "notes.txt";
    fs::copy_file(fs::path(BW_SOURCE_ROOT) / "materials/better_dipole.bssrdf", model);
    std::ofstream(text) << "not a model\n";
    auto p = start({"gui", "--size", "900x600", "--fresh"});
    const Window w = drawnWindow(*p);
    ASSERT_NE(w, 0u) << p->output();
    ASSERT_TRUE(dropFile(w, model, 450, 300)) << "the window did not take the drop";
    EXPECT_TRUE(p->waitForOutput("[info] opened " + model.string(), 30)) << p->output();
    ASSERT_TRUE(dropFile(w, text, 450, 300));
    EXPECT_TRUE(
        p->waitForOutput("dropped " + text.string() + ": not a file the workbench opens", 30))
        << p->output();
    EXPECT_TRUE(p->running());
    ::kill(p->pid(), SIGTERM);
    EXPECT_EQ(p->wait(20), 0) << p->output();
}

// A configuration folder that cannot be made (here a file stands where it would be): the window
// opens and closes as ever, and the session that could not be kept is an error naming where,
// with exit 1, not a silent loss.
TEST_F(GuiWindow, ASessionThatCannotBeSavedIsAnErrorWhenTheWindowCloses) {
    m_config = m_dir / "not_a_folder";
    std::ofstream(m_config) << "a file\n";
    auto p = start({"gui", "--size", "900x600"});
    ASSERT_NE(drawnWindow(*p), 0u) << p->output();
    ::kill(p->pid(), SIGTERM);
    EXPECT_EQ(p->wait(20), 1) << p->output();
    EXPECT_NE(p->output().find("error: the session was not saved: " + m_config.string() +
                               "/bssrdf-workbench/sessions/"),
              std::string::npos)
        << p->output();
}

// --out-dir is where a headless run writes: with a display and no --headless it is refused.
TEST_F(GuiWindow, OutDirWithADisplayAndNoHeadlessIsRefused) {
    auto p = start({"--out-dir", (m_dir / "out").string()});
    EXPECT_EQ(p->wait(30), 2) << p->output();
    EXPECT_NE(p->output().find("add --headless"), std::string::npos) << p->output();
    EXPECT_FALSE(fs::exists(m_dir / "out"));
}

} // namespace
