/*
 * input.h - the window's input as a queue of events. GLFW delivers key presses, characters,
 * clicks and wheel turns through callbacks as they happen; polling glfwGetKey once a frame
 * loses every tap shorter than a frame (most taps at 3-5 fps). Toggles act on queued presses;
 * motion keys use the held state, and a key pressed and released within one frame still counts
 * as held for that frame.
 */
#ifndef TP_APP_INPUT_H
#define TP_APP_INPUT_H

#define TP_INPUT_KEYS 512 /* > GLFW_KEY_LAST */
#define TP_INPUT_QUEUE 256

typedef enum tp_input_kind {
    TP_INPUT_NONE = 0,
    TP_INPUT_KEY,   /* key: GLFW key code, mods: GLFW modifier bits */
    TP_INPUT_CHAR,  /* key: Unicode code point typed (layout-aware: '?', '+') */
    TP_INPUT_CLICK, /* key: GLFW mouse button; x, y: cursor position, window coordinates */
} tp_input_kind;

typedef struct tp_input_event {
    tp_input_kind kind;
    int key, mods;
    double x, y;
} tp_input_event;

typedef struct tp_input {
    tp_input_event queue[TP_INPUT_QUEUE];
    int head, count, dropped;
    unsigned char held[TP_INPUT_KEYS];    /* down now */
    unsigned char pressed[TP_INPUT_KEYS]; /* went down since tp_input_begin_frame */
    double scroll_y;                      /* wheel steps since tp_input_begin_frame */
} tp_input;

/* Installs the callbacks on a GLFWwindow (passed as void* so that this header needs no GLFW)
 * and makes `in` its user pointer. `in` must outlive the window's event processing. */
void tp_input_attach(tp_input* in, void* glfw_window);

/* Starts a frame's input: clears the per-frame press marks and wheel steps. Call before
 * glfwPollEvents. */
void tp_input_begin_frame(tp_input* in);

/* Takes the oldest queued event; 0 when the queue is empty. */
int tp_input_next(tp_input* in, tp_input_event* out);

/* 1 while the key is down, or if it went down during this frame. */
int tp_input_held(const tp_input* in, int key);

/* Queues an event (the callbacks use it; tests may too). When the queue is full the event is
 * dropped and counted. */
void tp_input_push(tp_input* in, const tp_input_event* e);

#endif
