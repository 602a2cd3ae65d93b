// A minimal XDND drag source for the viewer tests: drops one file onto an X window the way a file manager does
// (XdndEnter, XdndPosition, XdndDrop, then the file's URI handed over through the XdndSelection selection), so
// `prism view`'s drop is tested through GLFW's own X11 drop handling. Exit 0 when the target accepted the drop
// and said it was finished, 1 with a one-line reason otherwise.
//
//   prism_xdnd_drop WINDOW_ID PATH
#include <X11/Xatom.h>
#include <X11/Xlib.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <string>

namespace {

int fail(const std::string& why) {
    std::fprintf(stderr, "prism_xdnd_drop: %s\n", why.c_str());
    return 1;
}

void send_client_message(Display* display, Window target, Atom type, long l0, long l1, long l2, long l3, long l4) {
    XEvent event{};
    event.xclient.type = ClientMessage;
    event.xclient.display = display;
    event.xclient.window = target;
    event.xclient.message_type = type;
    event.xclient.format = 32;
    event.xclient.data.l[0] = l0;
    event.xclient.data.l[1] = l1;
    event.xclient.data.l[2] = l2;
    event.xclient.data.l[3] = l3;
    event.xclient.data.l[4] = l4;
    XSendEvent(display, target, False, NoEventMask, &event);
    XFlush(display);
}

// Percent-encodes what a file URI must not hold literally.
std::string file_uri(const std::string& path) {
    std::string uri = "file://";
    for (unsigned char c : path) {
        if (std::isalnum(c) || std::strchr("/-_.~", c))
            uri += char(c);
        else {
            char escaped[4];
            std::snprintf(escaped, sizeof escaped, "%%%02X", c);
            uri += escaped;
        }
    }
    return uri + "\r\n";
}

}  // namespace

int main(int argc, char** argv) {
    if (argc != 3) return fail("usage: prism_xdnd_drop WINDOW_ID PATH");
    Window target = Window(std::strtoul(argv[1], nullptr, 0));
    std::string uri_list = file_uri(argv[2]);
    Display* display = XOpenDisplay(nullptr);
    if (!display) return fail("cannot open the X display");
    Window root = DefaultRootWindow(display);
    Window source = XCreateSimpleWindow(display, root, 0, 0, 1, 1, 0, 0, 0);
    Atom aware = XInternAtom(display, "XdndAware", False), enter = XInternAtom(display, "XdndEnter", False),
         position = XInternAtom(display, "XdndPosition", False), status = XInternAtom(display, "XdndStatus", False),
         drop = XInternAtom(display, "XdndDrop", False), finished = XInternAtom(display, "XdndFinished", False),
         selection = XInternAtom(display, "XdndSelection", False), copy = XInternAtom(display, "XdndActionCopy", False),
         uri_type = XInternAtom(display, "text/uri-list", False);

    // The target must say it takes drops, and which protocol version.
    Atom type;
    int format;
    unsigned long count, after;
    unsigned char* data = nullptr;
    if (XGetWindowProperty(display, target, aware, 0, 1, False, XA_ATOM, &type, &format, &count, &after, &data) !=
            Success ||
        count == 0)
        return fail("window " + std::string(argv[1]) + " is not XdndAware");
    long version = std::min(5L, long(*reinterpret_cast<Atom*>(data)));
    XFree(data);

    XSetSelectionOwner(display, selection, source, CurrentTime);
    int x = 0, y = 0;
    Window child;
    XTranslateCoordinates(display, target, root, 10, 10, &x, &y, &child);
    send_client_message(display, target, enter, long(source), version << 24, long(uri_type), None, None);
    send_client_message(display, target, position, long(source), 0, (long(x) << 16) | long(y), CurrentTime, long(copy));

    bool accepted = false, dropped = false;
    auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
    while (std::chrono::steady_clock::now() < deadline) {
        if (!XPending(display)) {
            struct timespec pause {
                0, 10 * 1000 * 1000
            };
            nanosleep(&pause, nullptr);
            continue;
        }
        XEvent event;
        XNextEvent(display, &event);
        if (event.type == ClientMessage && event.xclient.message_type == status && !dropped) {
            accepted = event.xclient.data.l[1] & 1;
            if (!accepted) return fail("the target refused the drop");
            send_client_message(display, target, drop, long(source), 0, CurrentTime, None, None);
            dropped = true;
        } else if (event.type == SelectionRequest) {
            // The target asks for the dropped data: the URI list, written into the property it names.
            XSelectionRequestEvent& request = event.xselectionrequest;
            XEvent reply{};
            reply.xselection.type = SelectionNotify;
            reply.xselection.requestor = request.requestor;
            reply.xselection.selection = request.selection;
            reply.xselection.target = request.target;
            reply.xselection.time = request.time;
            reply.xselection.property = None;
            if (request.target == uri_type) {
                XChangeProperty(display, request.requestor, request.property, uri_type, 8, PropModeReplace,
                                reinterpret_cast<const unsigned char*>(uri_list.data()), int(uri_list.size()));
                reply.xselection.property = request.property;
            }
            XSendEvent(display, request.requestor, False, NoEventMask, &reply);
            XFlush(display);
        } else if (event.type == ClientMessage && event.xclient.message_type == finished) {
            XDestroyWindow(display, source);
            XCloseDisplay(display);
            return 0;
        }
    }
    return fail(accepted ? "no XdndFinished from the target" : "no XdndStatus from the target");
}
