-- HMPL 16.5: StopAllTask stops every task, the caller too.
StartTaskFunc(1, "Forever")
Print("before StopAllTask")
StopAllTask()
Print("never printed: StopAllTask stopped this task")
