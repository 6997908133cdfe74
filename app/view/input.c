/* input.c - GLFW callbacks into an event queue (see input.h). */
#include "input.h"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <string.h>

void tp_input_push(tp_input* in, const tp_input_event* e)
{
    if (in->count == TP_INPUT_QUEUE) {
        in->dropped++;
        return;
    }
    in->queue[(in->head + in->count) % TP_INPUT_QUEUE] = *e;
    in->count++;
}

static tp_input* input_of(GLFWwindow* w)
{
    return (tp_input*)glfwGetWindowUserPointer(w);
}

static void on_key(GLFWwindow* w, int key, int scancode, int action, int mods)
{
    (void)scancode;
    tp_input* in = input_of(w);
    if (key < 0 || key >= TP_INPUT_KEYS)
        return;
    if (action == GLFW_PRESS) {
        in->held[key] = 1;
        in->pressed[key] = 1;
    } else if (action == GLFW_RELEASE) {
        in->held[key] = 0;
    }
    if (action == GLFW_PRESS || action == GLFW_REPEAT)
        tp_input_push(in, &(tp_input_event){.kind = TP_INPUT_KEY, .key = key, .mods = mods});
}

static void on_char(GLFWwindow* w, unsigned int codepoint)
{
    tp_input_push(input_of(w), &(tp_input_event){.kind = TP_INPUT_CHAR, .key = (int)codepoint});
}

static void on_button(GLFWwindow* w, int button, int action, int mods)
{
    if (action != GLFW_PRESS)
        return;
    tp_input_event e = {.kind = TP_INPUT_CLICK, .key = button, .mods = mods};
    glfwGetCursorPos(w, &e.x, &e.y);
    tp_input_push(input_of(w), &e);
}

static void on_scroll(GLFWwindow* w, double dx, double dy)
{
    (void)dx;
    input_of(w)->scroll_y += dy;
}

void tp_input_attach(tp_input* in, void* glfw_window)
{
    GLFWwindow* w = glfw_window;
    memset(in, 0, sizeof *in);
    glfwSetWindowUserPointer(w, in);
    glfwSetKeyCallback(w, on_key);
    glfwSetCharCallback(w, on_char);
    glfwSetMouseButtonCallback(w, on_button);
    glfwSetScrollCallback(w, on_scroll);
}

void tp_input_begin_frame(tp_input* in)
{
    memset(in->pressed, 0, sizeof in->pressed);
    in->scroll_y = 0;
}

int tp_input_next(tp_input* in, tp_input_event* out)
{
    if (in->count == 0)
        return 0;
    *out = in->queue[in->head];
    in->head = (in->head + 1) % TP_INPUT_QUEUE;
    in->count--;
    return 1;
}

int tp_input_held(const tp_input* in, int key)
{
    return key >= 0 && key < TP_INPUT_KEYS && (in->held[key] || in->pressed[key]);
}
