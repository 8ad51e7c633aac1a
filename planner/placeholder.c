typedef int ea__planner_placeholder;
